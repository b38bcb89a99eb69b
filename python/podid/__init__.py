"""podid: identification of nonlinear structures by POD and wavelet ridges.

The compiled extension ``podid._podid`` does the work; this package re-exports
it. Arrays are NumPy float64; a (sensors x samples) matrix in Fortran order is
read without a copy. podid's input errors are raised as ValueError with
podid's message.
"""
from ._podid import (  # noqa: F401
    Objective,
    PodResult,
    RidgeTrack,
    Scalogram,
    SimulationResult,
    TimeSeries,
    cwt,
    identify,
    instantaneous_frequency,
    landscape,
    pod,
    read,
    ridges,
    simulate,
)

__all__ = [
    "Objective", "identify", "landscape",
    "PodResult", "RidgeTrack", "Scalogram", "SimulationResult", "TimeSeries",
    "cwt", "instantaneous_frequency", "pod", "read", "ridges", "simulate",
]
