"""How the bindings take their arguments: real arrays only (a complex one lost
its imaginary part), errors naming the Python argument (not pybind11's
"incompatible function arguments", nor the library's field names), ints past
2**31 and 2**63, int keywords that refuse floats and None, and strict bools.
Run by ctest (python.pytest) with PYTHONPATH=<build>/python."""
import os
import pathlib
import re

import numpy as np
import pytest

import podid

SOURCE = pathlib.Path(os.environ.get("PODID_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CASE = str(SOURCE / "examples" / "beam.toml")
MEASURED_01S = str(SOURCE / "tests" / "data" / "measured_knl50_T0.1.csv")
MEASURED_1S = str(SOURCE / "examples" / "measured_knl50_T1.0.csv")

STEP = 1e-3
X = np.cos(2 * np.pi * 40 * np.arange(2000) * STEP)
# Every function taking a signal x, with keywords that keep it fast.
SIGNAL_FUNCTIONS = {
    "cwt": lambda x, **kw: podid.cwt(x, STEP, fmin=20, fmax=80, **kw),
    "ridges": lambda x, **kw: podid.ridges(x, STEP, fmin=20, fmax=80, **kw),
    "synchrosqueeze": lambda x, **kw: podid.synchrosqueeze(x, STEP, fmin=20, fmax=80, **kw),
    "instantaneous_frequency": lambda x, **kw: podid.instantaneous_frequency(x, STEP, fmin=20, fmax=80, **kw),
}


@pytest.mark.parametrize("name", SIGNAL_FUNCTIONS)
def test_a_signal_must_be_a_real_1d_array(name):
    f = SIGNAL_FUNCTIONS[name]
    for bad, got in ((X + 1j * X, "complex128"), (X.astype(np.complex64), "complex64"),
                     (None, "None"), (np.array(["a"] * 100), "<U1")):
        with pytest.raises(TypeError, match=re.escape(
                f"x: expected a real 1-D array (float or integer), got {got}")):
            f(bad)
    for bad, shape in ((np.ones((3, 4)), "(3, 4)"), (np.float64(1.0), "()")):
        with pytest.raises(ValueError, match=re.escape(
                f"x: expected a 1-D array, got a {np.ndim(bad)}-D array of shape {shape}")):
            f(bad)
    # The library's checks of the signal name x too.
    with pytest.raises(ValueError, match=r"^x: expected at least 4 samples, got 3 samples"):
        f(X[:3])
    with pytest.raises(ValueError, match=r"^x: expected finite values"):
        f(np.full(2000, np.nan))
    # Real input of any kind is converted to float64, as before.
    reference = f(X)
    for same in (X.astype(np.float32).astype(np.float64), list(X.astype(np.float32)), X.astype(np.float32)):
        assert type(f(same)) is type(reference)
    assert type(f(np.round(100 * X).astype(np.int64))) is type(reference)
    assert type(f((X > 0).astype(bool))) is type(reference)
    assert type(f(X[::-1])) is type(reference)  # not contiguous: copied


def test_float32_and_integer_signals_give_the_float64_transform():
    w = podid.cwt(X.astype(np.float32), STEP, fmin=20, fmax=80).coefficients
    np.testing.assert_array_equal(w, podid.cwt(X.astype(np.float32).astype(np.float64), STEP,
                                               fmin=20, fmax=80).coefficients)
    k = np.arange(2000) % 7
    np.testing.assert_array_equal(podid.cwt(k, STEP, fmin=20, fmax=80).coefficients,
                                  podid.cwt(k.astype(float), STEP, fmin=20, fmax=80).coefficients)


def test_pod_refuses_a_complex_matrix():
    x = np.ones((2, 10)) + 1j
    with pytest.raises(TypeError, match=re.escape("X: expected a real 2-D array (float or integer), got complex128")):
        podid.pod(x)
    with pytest.raises(TypeError, match="^X: .*got None"):
        podid.pod(None)
    with pytest.raises(ValueError, match=r"^X: expected a non-empty"):
        podid.pod(np.ones((2, 0)))
    with pytest.raises(ValueError, match=r"^modes: expected <= min\(M, N\) = 2"):
        podid.pod(np.random.default_rng(1).standard_normal((2, 10)), modes=3)
    assert podid.pod(np.arange(20, dtype=np.int32).reshape(2, 10) ** 2).poms.shape[0] == 2


@pytest.mark.parametrize("call, keyword", [
    (lambda n: podid.cwt(X, STEP, voices=n), "voices"),
    (lambda n: podid.cwt(X, STEP, threads=n), "threads"),
    (lambda n: podid.cwt(X, STEP, bins=n), "bins"),
    (lambda n: podid.ridges(X, STEP, count=n), "count"),
    (lambda n: podid.synchrosqueeze(X, STEP, fmin=20, fmax=80).ridges(n), "count"),
    (lambda n: podid.instantaneous_frequency(X, STEP, voices=n), "voices"),
    (lambda n: podid.plan(4000, STEP, threads=n), "threads"),
    (lambda n: podid.pod(np.ones((2, 10)), modes=n), "modes"),
    (lambda n: podid.Objective(CASE, MEASURED_01S, ridge_threads=n), "ridge_threads"),
    (lambda n: podid.Objective(CASE, MEASURED_01S, modes=n), "modes"),
    (lambda n: podid.identify(CASE, MEASURED_01S, multistart=n), "multistart"),
    (lambda n: podid.identify(CASE, MEASURED_01S, max_evaluations=n), "max_evaluations"),
    (lambda n: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, points=n), "points"),
    (lambda n: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, threads=n), "threads"),
])
def test_ints_beyond_a_c_int_are_value_errors_naming_the_keyword(call, keyword):
    for n in (2**31, -2**31 - 1, 2**62):
        with pytest.raises(ValueError, match=rf"^{keyword}: expected .*, got {n}$"):
            call(n)


# Every int keyword of every function (each macro-shared keyword once per
# function): each is checked by the bindings before any work.
SST = None


def _sst_ridges(n):
    global SST
    if SST is None:
        SST = podid.synchrosqueeze(X, STEP, fmin=20, fmax=80)
    return SST.ridges(n)


INT_KEYWORDS = [
    (lambda n: podid.pod(np.ones((2, 10)), modes=n), "modes"),
    (lambda n: podid.cwt(X, STEP, voices=n), "voices"),
    (lambda n: podid.cwt(X, STEP, threads=n), "threads"),
    (lambda n: podid.cwt(X, STEP, bins=n), "bins"),
    (lambda n: podid.ridges(X, STEP, count=n), "count"),
    (lambda n: podid.ridges(X, STEP, voices=n), "voices"),
    (lambda n: podid.ridges(X, STEP, threads=n), "threads"),
    (lambda n: podid.ridges(X, STEP, bins=n), "bins"),
    (lambda n: podid.synchrosqueeze(X, STEP, voices=n), "voices"),
    (lambda n: podid.synchrosqueeze(X, STEP, threads=n), "threads"),
    (lambda n: podid.synchrosqueeze(X, STEP, bins=n), "bins"),
    (_sst_ridges, "count"),
    (lambda n: podid.instantaneous_frequency(X, STEP, voices=n), "voices"),
    (lambda n: podid.instantaneous_frequency(X, STEP, threads=n), "threads"),
    (lambda n: podid.instantaneous_frequency(X, STEP, bins=n), "bins"),
    (lambda n: podid.plan(n, STEP), "samples"),
    (lambda n: podid.plan(4000, STEP, voices=n), "voices"),
    (lambda n: podid.plan(4000, STEP, threads=n), "threads"),
    (lambda n: podid.plan(4000, STEP, bins=n), "bins"),
    (lambda n: podid.Objective(CASE, MEASURED_01S, modes=n), "modes"),
    (lambda n: podid.Objective(CASE, MEASURED_01S, ridge_threads=n), "ridge_threads"),
    (lambda n: podid.identify(CASE, MEASURED_01S, multistart=n), "multistart"),
    (lambda n: podid.identify(CASE, MEASURED_01S, max_evaluations=n), "max_evaluations"),
    (lambda n: podid.identify(CASE, MEASURED_01S, seed=n), "seed"),
    (lambda n: podid.identify(CASE, MEASURED_01S, modes=n), "modes"),
    (lambda n: podid.identify(CASE, MEASURED_01S, threads=n), "threads"),
    (lambda n: podid.identify(CASE, MEASURED_01S, ridge_threads=n), "ridge_threads"),
    (lambda n: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, points=n), "points"),
    (lambda n: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, threads=n), "threads"),
    (lambda n: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, modes=n), "modes"),
]
INT_IDS = [f"{i}-{keyword}" for i, (_, keyword) in enumerate(INT_KEYWORDS)]


@pytest.mark.parametrize("call, keyword", INT_KEYWORDS, ids=INT_IDS)
def test_ints_beyond_64_bits_are_value_errors_naming_the_keyword(call, keyword):
    # pybind11's int64 caster refused these as "incompatible function arguments".
    # seed, a uint64, takes 2**63 .. 2**64 - 1 but not -1.
    values = (2**64, 10**30, -2**63 - 1, -2**70) + ((-1,) if keyword == "seed" else (2**63,))
    for n in values:
        with pytest.raises(ValueError, match=rf"^{keyword}: expected .*, got {n}$"):
            call(n)
    for n in (np.uint64(2**64 - 1),) if keyword != "seed" else ():
        with pytest.raises(ValueError, match=rf"^{keyword}: expected .*, got {int(n)}$"):
            call(n)


def test_the_seed_takes_any_uint64():
    with pytest.raises(ValueError, match=r"^seed: expected 0 to 2\^64 - 1, got 18446744073709551616$"):
        podid.identify(CASE, MEASURED_01S, seed=2**64)
    with pytest.raises(ValueError, match=r"^seed: expected 0 to 2\^64 - 1, got -1$"):
        podid.identify(CASE, MEASURED_01S, seed=-1)
    # In range, the seed passes and the next check (the record's length) speaks.
    for seed in (0, 2**64 - 1, np.uint64(2**64 - 1)):
        with pytest.raises(ValueError, match=r"^measured data: "):
            podid.identify(CASE, MEASURED_01S, seed=seed)


@pytest.mark.parametrize("call, keyword", INT_KEYWORDS, ids=INT_IDS)
def test_int_keywords_refuse_floats_and_none_naming_the_keyword(call, keyword):
    # A float is refused even when integral (2.0), as numpy and range() refuse it.
    for bad, got in ((1.5, "float"), (2.0, "float"), (None, "NoneType"), ("3", "str"),
                     (np.float64(2.0), "numpy.float64"), (np.bool_(True), r"numpy\.bool_?"),
                     (1 + 0j, "complex")):
        if keyword == "bins" and bad is None:
            continue  # bins=None: the log grid of `voices`
        with pytest.raises(TypeError, match=rf"^{keyword}: expected an int, got {got}$"):
            call(bad)


def test_int_keywords_take_python_and_numpy_integers():
    reference = podid.cwt(X, STEP, fmin=20, fmax=80, voices=8, threads=1).coefficients
    for voices, threads in ((np.int64(8), np.uint8(1)), (np.int32(8), True)):
        np.testing.assert_array_equal(
            podid.cwt(X, STEP, fmin=20, fmax=80, voices=voices, threads=threads).coefficients,
            reference)
    linear = podid.cwt(X, STEP, fmin=20, fmax=80, bins=16).frequencies_Hz
    np.testing.assert_array_equal(podid.cwt(X, STEP, fmin=20, fmax=80, bins=np.int16(16)).frequencies_Hz,
                                  linear)
    assert len(podid.ridges(X, STEP, fmin=20, fmax=80, count=np.int64(2))) == 2
    assert podid.pod(np.ones((2, 10)) + np.eye(2, 10), modes=np.int64(1)).poms.shape == (2, 1)


def test_plan_takes_a_large_sample_count_and_names_it():
    with pytest.raises(ValueError, match=r"^samples: expected at most 2\^27"):
        podid.plan(2**31, STEP)


def test_library_messages_name_the_keywords():
    with pytest.raises(ValueError, match=r"^penalty_s: expected"):
        podid.ridges(X, STEP, penalty_s=1e308)
    with pytest.raises(ValueError, match=r"^threshold: expected a value in \[0, 1\), got -1$"):
        podid.synchrosqueeze(X, STEP, threshold=-1)


@pytest.mark.parametrize("keywords, message", [
    (dict(fmin=float("nan")), r"^fmin: expected a finite value > 0, got nan$"),
    (dict(ridge_threads=0), r"^ridge_threads: expected 1\.\.256, got 0$"),
    (dict(fmax=1e9), r"^fmax: expected <= the Nyquist frequency"),
    (dict(fmin=1e-300), r"raise fmin or give a longer record"),
])
def test_objective_messages_name_the_keywords(keywords, message):
    with pytest.raises(ValueError, match=message) as caught:
        podid.Objective(CASE, MEASURED_1S, weightings=["wavelet"], **keywords)
    text = str(caught.value)
    for leak in ("objective options", "FrequencyGrid", "CwtOptions", "Cwt:", "--"):
        assert leak not in text


def test_instantaneous_frequency_memory_advice_names_its_own_keywords():
    x = np.cos(2 * np.pi * 50.0 * np.arange(100000) * 1e-4)
    with pytest.raises(ValueError, match=r"max_memory_MB\)") as caught:
        podid.instantaneous_frequency(x, 1e-4, max_memory_MB=1)
    assert "band_limited" not in str(caught.value)
    assert "a larger max_memory_MB" in str(caught.value)


@pytest.mark.parametrize("call, keyword", [
    (lambda b: podid.cwt(X, STEP, band_limited=b), "band_limited"),
    (lambda b: podid.ridges(X, STEP, band_limited=b), "band_limited"),
    (lambda b: podid.synchrosqueeze(X, STEP, band_limited=b), "band_limited"),
    (lambda b: podid.pod(np.ones((2, 10)), remove_mean=b), "remove_mean"),
    (lambda b: podid.pod(np.ones((2, 10)), time_modes=b), "time_modes"),
    (lambda b: podid.simulate(CASE, noise=b), "noise"),
    (lambda b: podid.Objective(CASE, MEASURED_01S, raw_sigma=b), "raw_sigma"),
    (lambda b: podid.Objective(CASE, MEASURED_01S, keep_mean=b), "keep_mean"),
    (lambda b: podid.identify(CASE, MEASURED_01S, keep_mean=b), "keep_mean"),
    (lambda b: podid.landscape(CASE, MEASURED_01S, "knl", 40, 60, keep_mean=b), "keep_mean"),
])
def test_bool_keywords_take_only_true_or_false(call, keyword):
    for bad, got in ((None, "NoneType"), (float("nan"), "float"), (2, "int"), ("yes", "str")):
        with pytest.raises(TypeError, match=rf"^{keyword}: expected True or False, got {got}$"):
            call(bad)


def test_numpy_bools_are_bools():
    a = podid.cwt(X, STEP, fmin=20, fmax=80, band_limited=np.bool_(True))
    assert a.decimation == podid.cwt(X, STEP, fmin=20, fmax=80, band_limited=True).decimation > 1
    assert podid.cwt(X, STEP, fmin=20, fmax=80, band_limited=np.True_ & False).decimation == 1


def test_a_result_beyond_the_largest_double_is_an_overflow_error():
    # The library's std::overflow_error: the in-band signal and the ridge's
    # amplitude of a tone at the largest double came back inf.
    t = np.arange(2000) * 1e-3
    y = np.finfo(float).max * np.cos(2 * np.pi * 40 * t)
    with pytest.raises(OverflowError, match="InverseCwt: the reconstruction overflowed"):
        podid.inverse_cwt(podid.cwt(y, 1e-3))
    with pytest.raises(OverflowError, match="amplitude overflowed"):
        podid.instantaneous_frequency(y, 1e-3)
