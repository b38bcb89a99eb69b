#!/usr/bin/python3
"""Writes scipy_rich_v5.mat and scipy_rich_v5_compressed.mat: a time series
(t, w) beside a struct (with a nested struct and a one-field small-element
name), a cell array, a string, a sparse matrix, int8 and logical arrays and an
empty matrix, as scipy.io.savemat (an independent .mat writer) lays them out.
w[i, j] = sin(0.1 i + j), t[i] = 1e-3 i, 100 samples x 3 channels."""
import numpy as np
import scipy.io as sio
import scipy.sparse as sp

i = np.arange(100)
t = i * 1e-3
w = np.sin(0.1 * i[:, None] + np.arange(3)[None, :])
extra = {
    "info": {"name": "beam", "k": np.array([1, 2, 3]), "nested": {"a": 1.5}},
    "cells": np.array([[1, "abc", np.zeros((2, 2))]], dtype=object),
    "label": "hello world",
    "S": sp.csc_matrix(np.eye(5)),
    "i8": np.arange(10, dtype=np.int8),
    "e": np.zeros((0, 3)),
    "b": np.array([True, False]),
}
for name, compress in (("scipy_rich_v5.mat", False), ("scipy_rich_v5_compressed.mat", True)):
    sio.savemat(name, dict(t=t, w=w, **extra), do_compression=compress)
