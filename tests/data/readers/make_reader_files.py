#!/usr/bin/python3
"""Writes the reader test files of tests/core/io_*_test.cpp with writers
independent of podid: scipy.io.savemat (MAT v5), h5py (MAT v7.3 = HDF5 with
MATLAB's 512-byte header) and a few lines of struct packing (UFF 58 / 58b, as
the I-DEAS data set 58 layout gives it). Run it in this folder with Debian's
/usr/bin/python3 (python3-scipy, python3-h5py); the files are committed, so the
tests need neither.

Signals (also computed in the tests): t_i = start + i * step,
  channel j (0-based) = (j + 1) * sin(2 pi (5 + 3 j) t_i)."""
import math
import struct

import numpy as np
import scipy.io as sio

N, START, STEP = 64, 0.5, 1.0 / 256.0  # UFF: start and step exact in E13.5
t = START + STEP * np.arange(N)
sig = np.stack([(j + 1) * np.sin(2 * np.pi * (5 + 3 * j) * t) for j in range(4)], axis=1)


# --- UFF 58 / 58b -------------------------------------------------------------
def header58(node, direction, ftype=1, dtype=2, count=N, start=START, step=STEP,
             unit="m/s^2", binary=None):
    lines = []
    if binary is not None:
        order, nbytes = binary
        lines.append("%6s%6i%6i%12i%12i%6i%6i%12i%12i" % ("58b", order, 2, 11, nbytes, 0, 0, 0, 0))
    else:
        lines.append("%6i" % 58)
    lines += ["accelerometer %d" % node, "NONE", "22-Nov-26 12:00:00", "NONE", "NONE"]
    lines.append("%5i%10i%5i%10i %-10s%10i%4i %-10s%10i%4i"
                 % (ftype, 0, 0, 0, "NONE", node, direction, "NONE", 0, 0))
    lines.append("%10i%10i%10i%13.5E%13.5E%13.5E" % (dtype, count, 1, start, step, 0.0))
    lines.append("%10i%5i%5i%5i %-20s %-20s" % (17, 0, 0, 0, "Time", "s"))
    lines.append("%10i%5i%5i%5i %-20s %-20s" % (12, 1, 0, 0, "Acceleration", unit))
    lines.append("%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE"))
    lines.append("%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE"))
    return lines


NODES = [(1, 3), (2, -2), (3, 1), (4, 3)]  # response node, direction: 1+Z 2-Y 3+X 4+Z


def ascii58(values, **kw):
    lines = ["%6i" % -1] + header58(**kw)
    for k in range(0, len(values), 6):  # 6E13.5; the last line is short
        lines.append("".join("%13.5E" % v for v in values[k:k + 6]))
    lines.append("%6i" % -1)
    return ("\n".join(lines) + "\n").encode()


def binary58(values, order, double, **kw):
    fmt = ("<" if order == 1 else ">") + ("d" if double else "f") * len(values)
    data = struct.pack(fmt, *values)
    head = ["%6i" % -1] + header58(dtype=4 if double else 2, binary=(order, len(data)), **kw)
    return ("\r\n".join(head) + "\r\n").encode() + data + ("%6i\r\n" % -1).encode()


def dataset151():  # a header data set, skipped with a note
    return b"    -1\n   151\nmodel\nNONE\nwritten by make_reader_files.py\n    -1\n"


def frf58():  # a frequency response function (type 4, complex single): skipped
    vals = [0.5, -0.25] * 6
    return ascii58(vals, node=9, direction=3, ftype=4, dtype=5, count=6, start=0.0, step=0.5)


with open("uff_four_accelerations_58b_le_single.uff", "wb") as f:
    f.write(dataset151())
    for j, (node, d) in enumerate(NODES):
        f.write(binary58(list(sig[:, j]), 1, False, node=node, direction=d))
    f.write(frf58())
with open("uff_four_accelerations_58b_be_double.uff", "wb") as f:
    for j, (node, d) in enumerate(NODES):
        f.write(binary58(list(sig[:, j]), 2, True, node=node, direction=d))
with open("uff_four_accelerations_58.uff", "wb") as f:
    for j, (node, d) in enumerate(NODES):
        f.write(ascii58(list(sig[:, j]), node=node, direction=d))
with open("uff_mismatched_grids.uff", "wb") as f:
    f.write(ascii58(list(sig[:, 0]), node=1, direction=3))
    f.write(ascii58(list(sig[:32, 1]), node=2, direction=3, count=32))
with open("uff_huge_count.uff", "wb") as f:  # declares 10^9 values in a few bytes
    f.write(ascii58(list(sig[:6, 0]), node=1, direction=3, count=1000000000))

# --- MAT v5: test-system export and plain structs (scipy) ----------------------
M, MSTART, MSTEP = 300, 0.25, 1.0 / 512.0
tm = MSTART + MSTEP * np.arange(M)
ym = np.stack([(j + 1) * np.sin(2 * np.pi * (5 + 3 * j) * tm) for j in range(3)], axis=1)
terms = np.zeros((1, 8), dtype=[("num", "O"), ("den", "O"), ("quantity", "O")])
for k, (q, e) in enumerate([("LENGTH", 1), ("ANGLE", 0), ("MASS", 0), ("TIME", -2),
                            ("CURRENT", 0), ("LIGHT", 0), ("TEMPERATURE", 0),
                            ("MOLCULAR_AMOUNT", 0)]):
    terms[0, k] = (np.array([[e]], dtype=np.int16), np.array([[1]], dtype=np.uint8), q)


def quantity(label, factor):
    return {"label": label,
            "unit_transformation": {"offset": np.uint8(0), "factor": factor, "log_reference": np.uint8(1)},
            "quantity_terms": terms, "info": "Data saved in MKS"}


def signal(values, names, label, factor, n=M):
    return {"x_values": {"start_value": MSTART, "increment": MSTEP,
                         "number_of_values": np.int32(n), "quantity": quantity("s", np.uint8(1))},
            "y_values": {"values": values, "quantity": quantity(label, factor)},
            "function_record": {"name": names, "type": "Signal"}}


names = np.empty((1, 3), dtype=object)
names[0, :] = ["1:WING:+Z", "2:WING:-X", "3:TAIL:+Y"]
sio.savemat("testsystem_export.mat", {
    "Signal_0": signal(ym, names, "g", 0.10197162129779283),     # samples x channels
    "Signal_1": signal(ym[:, 0][None, :], "4:SHAKER:+Z", "N", np.uint8(1)),  # 1 x samples
    "Signal_2": signal(ym.T.copy(), names, "m/s^2", np.uint8(1)),  # channels x samples
})
sio.savemat("plain_struct.mat", {
    "fs": 512.0,
    "data": {"note": "plain struct", "fs": 512.0, "time": tm, "acc1": ym[:, 0],
             "acc2": ym[:, 1][:, None], "both": ym[:, 1:].T.copy()},
    "notime": {"a": ym[:, 0], "b": ym[:, 2]},
    "withfs": {"fs": 512.0, "x": ym[:, 0], "y": ym[:, 1]},
})

# --- MAT v7.3 (HDF5) ------------------------------------------------------------
import h5py  # noqa: E402


def mat73(name, fill):
    with h5py.File(name, "w", userblock_size=512) as f:
        fill(f)
    header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sun Nov 22 12:00:00 2026 HDF5 schema 1.00 ."
    with open(name, "r+b") as f:
        f.write(header.ljust(116, b" ") + b"\0" * 8 + b"\x00\x02IM")


def matlab_class(obj, name):
    # As MATLAB writes it: a scalar fixed-length string, NULLTERM padded (libmatio
    # does not recognise h5py's default NULLPAD strings).
    tid = h5py.h5t.C_S1.copy()
    tid.set_size(len(name))
    tid.set_strpad(h5py.h5t.STR_NULLTERM)
    attr = h5py.h5a.create(obj.id, b"MATLAB_class", tid, h5py.h5s.create(h5py.h5s.SCALAR))
    attr.write(np.array(name.encode(), dtype="S%d" % len(name)), mtype=tid)


def double(group, name, array):
    # MATLAB stores an m x n array as an HDF5 dataset of shape (n, m).
    d = group.create_dataset(name, data=np.asarray(array, dtype=np.float64).T)
    matlab_class(d, "double")
    return d


def v73_matrix(f):
    double(f, "t", tm[None, :])  # 1 x 300
    double(f, "w", ym.T)         # 3 x 300: channels x samples
    g = f.create_group("data")   # a plain struct
    matlab_class(g, "struct")
    fields = np.empty(3, dtype=object)  # MATLAB_fields: variable-length char arrays
    for k, n in enumerate(("time", "a", "b")):
        fields[k] = np.array([c.encode() for c in n], dtype="S1")
    g.attrs.create("MATLAB_fields", data=fields, dtype=h5py.vlen_dtype(np.dtype("S1")))
    double(g, "time", tm[:, None])      # 300 x 1
    double(g, "a", ym[:, 0][None, :])   # 1 x 300
    double(g, "b", ym[:, 2][:, None])   # 300 x 1


def unwritten(count):
    def fill(f):
        rng = np.random.default_rng(1)
        double(f, "noise", rng.standard_normal((1, 8000)))  # 64 kB that do not compress
        d = f.create_dataset("w", shape=(count, 1), dtype="f8", chunks=(65536, 1))
        matlab_class(d, "double")  # chunks never written
    return fill


mat73("v73_matrix.mat", v73_matrix)
mat73("v73_unwritten_3e8.mat", unwritten(300_000_000))
mat73("v73_unwritten_5e7.mat", unwritten(50_000_000))
with open("v73_matrix.mat", "rb") as f:
    whole = f.read()
with open("v73_truncated.mat", "wb") as f:
    f.write(whole[: len(whole) // 2])
