"""podid: identification of nonlinear structures by POD and wavelet ridges.

The compiled extension ``podid._podid`` does the work; this package re-exports
it. Arrays are NumPy float64; a (sensors x samples) matrix in Fortran order is
read without a copy. podid's input errors are raised as ValueError with
podid's message.
"""
from . import _podid
from ._podid import (  # noqa: F401
    Objective,
    PodResult,
    RidgeTrack,
    Scalogram,
    SimulationResult,
    SynchrosqueezedTransform,
    TimeSeries,
    cwt,
    instantaneous_frequency,
    inverse_cwt,
    pod,
    read,
    ridges,
    simulate,
    synchrosqueeze,
)

__all__ = [
    "Objective", "identify", "landscape", "plan",
    "PodResult", "RidgeTrack", "Scalogram", "SimulationResult", "SynchrosqueezedTransform",
    "TimeSeries", "cwt", "instantaneous_frequency", "inverse_cwt", "pod", "read", "ridges",
    "simulate", "synchrosqueeze",
]


class Result(dict):
    """A dict whose keys are also attributes: ``result.parameters["knl"]``."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return list(self.keys())


def identify(*args, **kwargs):
    return Result(_podid.identify(*args, **kwargs))


def landscape(*args, **kwargs):
    return Result(_podid.landscape(*args, **kwargs))


def plan(*args, **kwargs):
    return Result(_podid.plan(*args, **kwargs))


identify.__doc__ = _podid.identify.__doc__
landscape.__doc__ = _podid.landscape.__doc__
plan.__doc__ = _podid.plan.__doc__
