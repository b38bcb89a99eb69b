# Every dependency comes from a Debian package; nothing is vendored.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(PkgConfig REQUIRED)
# FFTW: build/fftw-simd first when scripts/build-fftw.sh made it (Debian's
# fftw3 source with AVX2/AVX-512 codelets; the presets put it in
# CMAKE_PREFIX_PATH), else Debian's libfftw3-dev.
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET GLOBAL fftw3)
message(STATUS "podid: FFTW ${FFTW3_VERSION} from ${FFTW3_LINK_LIBRARIES}")
# scripts/build-fftw.sh's FFTW (its AVX2/AVX-512 codelets) prefers other
# plans: wavelet/src/full_rate.hpp's kInPlaceLength follows it.
if(FFTW3_LIBDIR MATCHES "/fftw-simd/lib$")
  set(PODID_FFTW_SIMD_CODELETS ON)
else()
  set(PODID_FFTW_SIMD_CODELETS OFF)
endif()
pkg_check_modules(MATIO REQUIRED IMPORTED_TARGET GLOBAL matio)
# v7.3 .mat files: dataset storage checked and HDF5's own error printing
# silenced before libmatio reads them (the HDF5 libmatio is built with).
pkg_check_modules(HDF5 REQUIRED IMPORTED_TARGET GLOBAL hdf5)
find_package(ZLIB REQUIRED)  # .mat structure checks inflate compressed variables
find_package(GSL REQUIRED)
find_package(METIS REQUIRED)  # cmake/FindMETIS.cmake
find_package(NLopt REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
# Spectra (libspectra-dev, header-only): the sparse eigensolver of BeamModel::Modes.
find_path(SPECTRA_INCLUDE_DIR Spectra/SymGEigsShiftSolver.h REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(Threads REQUIRED)
if(PODID_BUILD_APPS)
  find_package(CLI11 REQUIRED)
endif()
if(PODID_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(PODID_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
