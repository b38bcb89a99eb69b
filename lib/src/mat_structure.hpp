#pragma once
// Structural checks of MATLAB .mat files made before libmatio reads them (not
// installed). libmatio trusts the sizes in a file's headers and allocates them
// before it notices that the file cannot hold them: a 424-byte file can make it
// ask for 24 GB. These walks read every header of the file (inflating
// compressed variables as a stream, in bounded memory) and throw
// std::invalid_argument, naming the byte, when a header declares more than the
// bytes that follow it can hold.

#include <string>

namespace podid::internal {

/// Checks a .mat file before Mat_Open (which already reads the first v4
/// header): level 5 files (v5, v6, v7: the 128-byte header with version
/// 0x0100) as below; v7.3 (HDF5, version 0x0200) is left to libmatio and
/// HDF5; anything else is read as level 4, as libmatio does.
///
/// Level 5: for every data element at any depth (inside miCOMPRESSED too), its
/// size fits in its parent; for every miMATRIX, its elements fit in its
/// remaining bytes (char arrays: one byte each at least, as int8 storage; cell
/// arrays and function handles: an 8-byte tag per cell; structs and objects:
/// an 8-byte tag per field of each element; opaque and unknown classes: as
/// cell arrays). A numeric array's real and imaginary parts are each an
/// element of a numeric type with exactly the array's values: libmatio reads
/// that many values of the element's type whatever its size, and none of a
/// type it does not convert, leaving the array uninitialised. A sparse array's
/// row indices and column pointers are int32 elements and its values an
/// element of a numeric type, each of a whole number of values (its dimensions
/// do not bound its storage). Format:
/// MATLAB's "MAT-File Format", ch. 1.
///
/// Level 4: every matrix's name length and data size fit in the rest of the
/// file. Format: "MAT-File Format", ch. 2 (20-byte headers of type, mrows,
/// ncols, imagf, namlen).
void CheckMatStructure(const std::string& path);

}  // namespace podid::internal
