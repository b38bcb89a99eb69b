"""The Python module against independent references: NumPy's SVD, the DOP853
reference data of tests/data, analytic tones. Run by ctest (python.pytest)
with PYTHONPATH=<build>/python."""
import json
import math
import os
import pathlib
import re

import numpy as np
import pytest

import podid

SOURCE = pathlib.Path(os.environ.get("PODID_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CASE = str(SOURCE / "examples" / "beam.toml")
CLEAN = str(SOURCE / "tests" / "data" / "clean_knl50_T0.1.csv")

# POD vs LAPACK's SVD (through NumPy): both are backward stable, so singular
# values agree to a few eps relative to sigma_1.
SVD_TOLERANCE = 1e-12
# Newmark (dt = 2e-4) against DOP853: its period error, the bound of
# tests/core/newmark_test.cpp (issue 2's acceptance).
NEWMARK_VS_DOP853 = 0.012
# A tone's IF along the ridge, away from the record's ends: the phase
# estimator is exact for a tone up to the filters' band tolerance (1e-12).
# Near the ends, inside the cone, the edge still moves it by up to ~1 % (the
# worst-case border figures are in docs/wavelet.md), so only the middle half
# is held to this.
TONE_IF_TOLERANCE_HZ = 1e-6
# Two tones (25 Hz, and 90 Hz at half the amplitude): each ridge's IF is
# modulated by the other tone's leakage through the wavelet's Gaussian
# (psi^ at 25/90 of the 90 Hz filter's centre is ~1e-4 of its peak), so
# the medians agree to ~1e-4 Hz x a few, not to round-off.
TWO_TONE_TOLERANCE_HZ = 1e-3


def centred(x):
    return x - x.mean(axis=1, keepdims=True)


def test_pod_matches_numpy_svd_for_every_method():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((6, 400)) * np.array([[5.0], [3.0], [2.0], [1.0], [0.5], [0.1]])
    u, s, vt = np.linalg.svd(centred(x), full_matrices=False)
    for method in ("svd", "direct", "snapshot", "auto"):
        r = podid.pod(x, method=method)
        assert r.poms.shape == (6, 6) and r.time_modes.shape == (400, 6)
        np.testing.assert_allclose(r.singular_values, s, rtol=0, atol=SVD_TOLERANCE * s[0] * 10)
        for k in range(6):  # same subspaces: |u_k . u_k'| = 1 up to sign
            assert abs(abs(u[:, k] @ r.poms[:, k]) - 1) < 1e-8
        np.testing.assert_allclose(r.proper_orthogonal_values, r.singular_values**2 / 400, rtol=1e-14)


def test_pod_accepts_c_and_fortran_arrays_and_truncates():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((4, 100))
    a = podid.pod(np.ascontiguousarray(x), modes=2)
    b = podid.pod(np.asfortranarray(x), modes=2)
    assert a.poms.shape == (4, 2)
    np.testing.assert_array_equal(a.singular_values, b.singular_values)


def test_pod_refuses_an_array_that_is_not_2d():
    # A 1-D array became one column: 100 sensors of 1 sample each.
    with pytest.raises(ValueError, match=r"X: expected a 2-D array \(sensors x samples\), got a 1-D"):
        podid.pod(np.arange(100.0))
    with pytest.raises(ValueError, match="got a 3-D"):
        podid.pod(np.ones((2, 3, 4)))
    # A nested list is an array too.
    assert podid.pod([[0.0, 1.0, 0.0, 2.0], [1.0, 0.0, 1.0, 0.0]]).poms.shape[0] == 2


def test_read_gives_its_notes_as_warnings():
    # The file's data sets 151 and a complex 58 are skipped, as podid notes.
    path = SOURCE / "tests" / "data" / "readers" / "uff_four_accelerations_58b_le_single.uff"
    with pytest.warns(UserWarning) as caught:
        series = podid.read(str(path))
    assert len(series.channel_names) == 4
    messages = [str(w.message) for w in caught]
    assert any("data set 151 skipped" in m for m in messages), messages
    assert any("function type 4, complex skipped" in m for m in messages), messages


def test_simulate_matches_the_independent_integration():
    reference = podid.read(CLEAN)
    sim = podid.simulate(CASE, noise=False)
    assert sim.completed, sim.message
    assert sim.sensors.channel_names == reference.channel_names == [f"w{i}" for i in range(1, 7)]
    np.testing.assert_allclose(sim.sensors.time_s, reference.time_s, rtol=0, atol=1e-12)
    error = np.linalg.norm(sim.sensors.values - reference.values) / np.linalg.norm(reference.values)
    assert error < NEWMARK_VS_DOP853


def test_simulate_takes_overrides_and_toml_text():
    text = pathlib.Path(CASE).read_text()
    linear = podid.simulate(text, set=["nonlinearity.0.k3=0"], noise=False)
    stiff = podid.simulate(CASE, set=["nonlinearity.0.k3=5e10"], noise=False)
    assert linear.completed and stiff.completed
    assert not np.allclose(linear.sensors.values, stiff.sensors.values)


# Superposition on the linear beam (k3 = 0, from rest): each step solves the
# same linear system, Newton to 1e-10 of the residual scale, so sums agree to
# ~1e-10 of the response; 1e-9 leaves a margin (tests/core/multi_force_test.cpp).
SUPERPOSITION_TOLERANCE = 1e-9


def test_several_forces_and_base_excitation_through_set():
    linear = ["nonlinearity.0.k3=0", "initial.static_tip_force=0"]
    first = ["force.0.type=harmonic", "force.0.node=3", "force.0.amplitude=4", "force.0.frequency=70"]
    second = ["force.{}.type=sweep", "force.{}.node=6", "force.{}.amplitude=-2",
              "force.{}.start_frequency=20", "force.{}.end_frequency=200"]
    base = ["base.type=harmonic", "base.amplitude=9.81", "base.frequency=15"]
    both = podid.simulate(CASE, set=linear + first + [k.format(1) for k in second] + base, noise=False)
    one = podid.simulate(CASE, set=linear + first, noise=False)
    two = podid.simulate(CASE, set=linear + [k.format(0) for k in second], noise=False)
    three = podid.simulate(CASE, set=linear + base, noise=False)
    assert both.completed and one.completed and two.completed and three.completed
    total = one.sensors.values + two.sensors.values + three.sensors.values
    scale = np.abs(both.sensors.values).max()
    assert np.abs(both.sensors.values - total).max() <= SUPERPOSITION_TOLERANCE * scale
    with pytest.raises(ValueError, match="force.1.node: expected"):
        podid.simulate(CASE, set=first + ["force.1.type=harmonic", "force.1.node=99",
                                          "force.1.amplitude=1", "force.1.frequency=5"])


def test_instantaneous_frequency_of_a_tone():
    step = 1e-3
    t = np.arange(4000) * step
    track = podid.instantaneous_frequency(np.cos(2 * math.pi * 40.0 * t), step, fmin=20, fmax=80)
    inside = track.inside_coi
    assert inside.sum() > 0.5 * len(inside)
    middle = (track.time_s > 1.0) & (track.time_s < 3.0)
    assert np.all(inside[middle])
    assert np.max(np.abs(track.frequency_Hz[middle] - 40.0)) < TONE_IF_TOLERANCE_HZ


def test_cwt_and_two_ridges_of_two_tones():
    step = 1e-3
    t = np.arange(4000) * step
    x = np.cos(2 * math.pi * 25.0 * t) + 0.5 * np.cos(2 * math.pi * 90.0 * t)
    sc = podid.cwt(x, step, fmin=10, fmax=200)
    assert sc.coefficients.shape == (4000, len(sc.frequencies_Hz))
    peak = sc.frequencies_Hz[np.argmax(np.abs(sc.coefficients[2000]))]
    assert abs(peak - 25.0) < 25.0 * (2 ** (1 / 32) - 1)
    tracks = podid.ridges(x, step, count=2, fmin=10, fmax=200)
    found = sorted(float(np.median(tr.frequency_Hz[(tr.time_s > 1) & (tr.time_s < 3)])) for tr in tracks)
    assert abs(found[0] - 25.0) < TWO_TONE_TOLERANCE_HZ and abs(found[1] - 90.0) < TWO_TONE_TOLERANCE_HZ


# A cosine on its grid frequency has |W| = 1 (L1 normalisation: half of
# Morlet's psi^(omega0) = 2); in the record's middle, far from both ends, only
# rounding is left (measured 4e-15).
UNIT_COSINE_TOLERANCE = 1e-12


def test_bins_give_a_linear_grid_as_the_cli_does():
    step = 1e-3
    t = np.arange(4000) * step
    x = np.cos(2 * math.pi * 40.0 * t)
    sc = podid.cwt(x, step, fmin=20, fmax=80, bins=61)
    np.testing.assert_allclose(sc.frequencies_Hz, np.linspace(20.0, 80.0, 61), rtol=1e-15, atol=0)
    row = np.abs(sc.coefficients[2000])
    assert np.argmax(row) == 20 and abs(row[20] - 1) < UNIT_COSINE_TOLERANCE
    middle = lambda tr: (tr.time_s > 1) & (tr.time_s < 3)
    track = podid.ridges(x, step, fmin=20, fmax=80, bins=61)[0]
    assert np.all(track.grid_frequency_Hz[middle(track)] == 40.0)
    assert np.max(np.abs(track.frequency_Hz[middle(track)] - 40.0)) < TONE_IF_TOLERANCE_HZ
    track = podid.instantaneous_frequency(x, step, fmin=20, fmax=80, bins=61)
    assert np.max(np.abs(track.frequency_Hz[middle(track)] - 40.0)) < TONE_IF_TOLERANCE_HZ
    assert len(podid.cwt(x, step, fmin=20, fmax=80).frequencies_Hz) == 65  # no bins: 32 voices, 2 octaves
    with pytest.raises(ValueError, match="^bins: expected 2..100000, got 1"):
        podid.synchrosqueeze(x, step, bins=1)


def test_plan_measures_once_into_the_cache_as_podid_plan_does(tmp_path, monkeypatch):
    # A length no earlier test planned (FFTW's wisdom lives for the process),
    # in an empty cache.
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    first = podid.plan(1001, 1e-3, fmin=20, fmax=100, padding="reflect")
    lengths = first.lengths
    count = sum(len(v) for v in lengths.values())
    assert first.measured == count and first.known == 0 and first.saved, first
    assert first.wisdom_path == str(tmp_path / "podid" / "fftw3-wisdom")
    assert (tmp_path / "podid" / "fftw3-wisdom").stat().st_size > 0
    # The full-rate path's padded length P, its inverses batched as P / D
    # points for D a power of two, and the band-limited path's shorter inverse.
    p = lengths["real_forward"][0]
    assert lengths["complex_forward"] == [p] and p in lengths["complex_backward"] and p >= 1001
    for m, batch in lengths["batched_backward"]:
        d = p // m
        assert m * d == p and d & (d - 1) == 0 and batch >= 1
    assert min(lengths["complex_backward"]) < p
    again = podid.plan(1001, 1e-3, fmin=20, fmax=100, padding="reflect")
    assert again.measured == 0 and again.known == count and not again.saved
    with pytest.raises(ValueError, match='^effort: expected one of measure, patient, got "fast"'):
        podid.plan(1001, 1e-3, effort="fast")
    with pytest.raises(ValueError, match="samples: expected at least 4, got 3"):
        podid.plan(3, 1e-3)


# 2 pi f s, a scale's frequency times the scale, against its analytic value:
# Morlet's omega0 (the peak of its spectrum, and the ridge of a tone with L1
# normalisation), Torrence & Compo's (omega0 + sqrt(2 + omega0^2)) / 2 for
# the ridge with L2; generalised Morse's peak (beta / gamma)^(1 / gamma) and
# its L2 ridge ((beta + 1/2) / gamma)^(1 / gamma), the maximum of
# sqrt(u) u^beta exp(-u^gamma). Only rounding separates them: 1e-12 relative.
SCALE_FREQUENCY_TOLERANCE = 1e-12
MORLET_OMEGA0, MORSE_GAMMA, MORSE_BETA = 6.0, 3.0, 20.0


@pytest.mark.parametrize("wavelet,normalisation,convention,expected", [
    ("morlet", "amplitude", "ridge", MORLET_OMEGA0),
    ("morlet", "energy", "ridge", (MORLET_OMEGA0 + math.sqrt(2 + MORLET_OMEGA0 ** 2)) / 2),
    ("morlet", "energy", "peak", MORLET_OMEGA0),
    ("morse", "amplitude", "ridge", (MORSE_BETA / MORSE_GAMMA) ** (1 / MORSE_GAMMA)),
    ("morse", "energy", "ridge", ((MORSE_BETA + 0.5) / MORSE_GAMMA) ** (1 / MORSE_GAMMA)),
    ("morse", "energy", "peak", (MORSE_BETA / MORSE_GAMMA) ** (1 / MORSE_GAMMA)),
])
def test_scale_frequency_conventions_match_their_analytic_values(wavelet, normalisation, convention,
                                                                expected):
    step = 1e-3
    x = np.cos(2 * math.pi * 40.0 * np.arange(1000) * step)
    sc = podid.cwt(x, step, fmin=20, fmax=80, wavelet=wavelet, omega0=MORLET_OMEGA0, gamma=MORSE_GAMMA,
                   beta=MORSE_BETA, normalisation=normalisation, scale_convention=convention)
    product = 2 * math.pi * sc.frequencies_Hz * sc.scales_s
    assert np.max(np.abs(product / expected - 1)) < SCALE_FREQUENCY_TOLERANCE


def test_ridge_options_morse_wavelet_and_the_scale_estimator_on_tones():
    step = 1e-3
    t = np.arange(4000) * step
    middle = (t > 1.0) & (t < 3.0)
    tone = np.cos(2 * math.pi * 40.0 * t)
    # Each estimator, wavelet and method reads a tone on the grid exactly
    # (the scale's parabola is exact for a tone with L1, docs/wavelet.md).
    for options in (dict(wavelet="morse"), dict(estimator="scale"), dict(method="max"),
                    dict(penalty_s=0.0)):
        (track,) = podid.ridges(tone, step, fmin=20, fmax=80, **options)
        assert np.max(np.abs(track.frequency_Hz[middle] - 40.0)) < TONE_IF_TOLERANCE_HZ, options
    # A 100 Hz tone above a 20-80 Hz grid: the ridge holds to the grid's top;
    # the phase derivative reads the tone, the scale the grid's top frequency.
    high = np.cos(2 * math.pi * 100.0 * t)
    (phase,) = podid.ridges(high, step, fmin=20, fmax=80)
    (scale,) = podid.ridges(high, step, fmin=20, fmax=80, estimator="scale")
    assert np.all(phase.grid_frequency_Hz[middle] == scale.grid_frequency_Hz[middle])
    top = float(np.max(podid.cwt(high, step, fmin=20, fmax=80).frequencies_Hz))
    assert np.all(scale.frequency_Hz[middle] == top)
    # W of a tone is that tone at every scale: exact off the grid too.
    assert np.max(np.abs(phase.frequency_Hz[middle] - 100.0)) < TONE_IF_TOLERANCE_HZ
    # Bad options are named by their keyword.
    for options, message in ((dict(method="viterbi"), "method: expected one of max, penalised"),
                             (dict(estimator="hilbert"), "estimator: expected one of phase, scale"),
                             (dict(penalty_s=-1.0), "penalty_s: expected a finite value >= 0"),
                             (dict(count=17), "count: expected 1..16"),
                             (dict(wavelet="haar"), "wavelet: expected one of morlet, morse"),
                             (dict(wavelet="morse", gamma=0.5), "gamma: expected a value in [1, 20]"),
                             (dict(scale_convention="centre"), "scale_convention: expected one of ridge, peak"),
                             (dict(padding="mirror"), "padding: expected one of reflect, zero, periodic")):
        with pytest.raises(ValueError, match=re.escape(message)):
            podid.ridges(tone, step, fmin=20, fmax=80, **options)


# The synchrosqueezed ridges of two tones in 0.3-1.7 s: the IF at the
# reassignment's fixed point is exact for a tone up to the other tone's leak
# into its scales (measured 1.6e-9 Hz at 20 Hz; 0.027 Hz at 60 Hz, the 20 Hz
# tone's 40 Hz x 2 e^-8: docs/wavelet.md). The bounds: the C++ test's 1e-6
# Hz (Synchrosqueeze.TwoRidgesFollowTwoTones), and about twice the leak.
SST_TONE_TOLERANCE_HZ = (1e-6, 0.06)
# The inverse CWT of an in-band tone: the reconstruction bound
# (1.8e-5 measured).
INVERSE_TOLERANCE = 1e-3


def test_synchrosqueezed_ridges_of_two_tones():
    step = 1e-3
    t = np.arange(2001) * step
    x = np.cos(2 * math.pi * 20.0 * t) + 0.5 * np.cos(2 * math.pi * 60.0 * t)
    sst = podid.synchrosqueeze(x, step)
    assert sst.sst.coefficients.shape == (2001, len(sst.sst.frequencies_Hz))
    assert sst.reassigned_frequency_Hz.shape == sst.sst.coefficients.shape
    # T gathers each tone into one bin: at t = 1 s the two largest |T| are
    # the grid frequencies nearest 20 and 60 Hz.
    top = np.sort(sst.sst.frequencies_Hz[np.argsort(np.abs(sst.sst.coefficients[1000]))[-2:]])
    assert abs(math.log(top[0] / 20.0)) < math.log(2) / 64 and abs(math.log(top[1] / 60.0)) < math.log(2) / 64
    tracks = sst.ridges(2)
    middle = (tracks[0].time_s >= 0.3) & (tracks[0].time_s <= 1.7)
    # One ridge per tone (either order), each within its bound at every time.
    tones = sorted(((float(np.median(tr.frequency_Hz[middle])), tr) for tr in tracks), key=lambda p: p[0])
    assert [round(f) for f, _ in tones] == [20, 60]
    for (f, tr), tolerance in zip(tones, SST_TONE_TOLERANCE_HZ):
        assert np.max(np.abs(tr.frequency_Hz[middle] - round(f))) < tolerance
    with pytest.raises(ValueError, match=r"^threshold: expected a value in \[0, 1\), got 1.5$"):
        podid.synchrosqueeze(x, step, threshold=1.5)


def test_a_second_synchrosqueezed_ridge_of_one_tone_is_nan_where_t_is_empty():
    # |T| of one tone is 0 outside a few bins of it: the second ridge has
    # times with no cell (this crashed the interpreter before), which get NaN.
    step = 1e-3
    t = np.arange(2001) * step
    tracks = podid.synchrosqueeze(np.cos(2 * math.pi * 40.0 * t), step).ridges(2)
    assert len(tracks) == 2
    assert np.isnan(tracks[1].frequency_Hz).any()
    middle = (tracks[0].time_s >= 0.3) & (tracks[0].time_s <= 1.7)
    assert np.max(np.abs(tracks[0].frequency_Hz[middle] - 40.0)) < SST_TONE_TOLERANCE_HZ[0]


def test_inverse_cwt_returns_the_in_band_tone():
    step = 1e-3
    t = np.arange(2001) * step
    tone = np.cos(2 * math.pi * 30.0 * t)
    x = tone + np.cos(2 * math.pi * 300.0 * t)  # far above the 10-120 Hz grid
    sc = podid.cwt(x, step)
    y = podid.inverse_cwt(sc)
    middle = (sc.time_s >= 0.3) & (sc.time_s <= 1.7)
    rms = np.sqrt(np.mean((y[middle] - tone[middle]) ** 2) / np.mean(tone[middle] ** 2))
    assert rms < INVERSE_TOLERANCE


def test_errors_are_value_errors_with_podid_messages():
    with pytest.raises(ValueError, match="svd"):
        podid.pod(np.ones((2, 10)), method="qr")
    with pytest.raises(ValueError, match="nonlinearity.0.k3"):
        podid.simulate(CASE, set=["nonlinearity.0.k3=abc"])
    with pytest.raises(ValueError, match="Nyquist|frequency"):
        podid.cwt(np.sin(np.arange(100.0)), 1e-3, fmin=10, fmax=900)
    with pytest.raises(ValueError, match="no_such_file"):
        podid.read("/no_such_file.csv")


def test_a_file_without_time_names_the_keyword_arguments():
    # The readers name the CLI's --rate/--step; Python's are rate_Hz/step_s.
    plain = str(SOURCE / "tests" / "data" / "readers" / "plain_struct.mat")
    with pytest.raises(ValueError, match=r"or a sampling step \(rate_Hz, step_s\), got none"):
        podid.read(plain, variable="notime")
    assert podid.read(plain, variable="notime", rate_Hz=512.0).step_s == pytest.approx(1.0 / 512.0)


def test_wavelet_errors_name_the_keyword_arguments():
    # They named the library's fields (FrequencyGrid.min_frequency_Hz, ...).
    x = np.sin(np.arange(1000.0))
    with pytest.raises(ValueError, match=r"^fmin: expected a finite value > 0, got nan$"):
        podid.cwt(x, 1e-3, fmin=float("nan"))
    with pytest.raises(ValueError, match=r"^fmax: expected <= the Nyquist frequency"):
        podid.cwt(x, 1e-3, fmax=900)
    with pytest.raises(ValueError, match=r"^fmax: expected a finite value > fmin \(200\)"):
        podid.ridges(x, 1e-3, fmin=200, fmax=100)
    with pytest.raises(ValueError, match=r"^voices: expected 1\.\.1024, got 0$"):
        podid.synchrosqueeze(x, 1e-3, voices=0)
    with pytest.raises(ValueError, match=r"^omega0: expected >= 5, got 0.1$"):
        podid.instantaneous_frequency(x, 1e-3, omega0=0.1)
    with pytest.raises(ValueError, match=r"^coi_factor: expected a value in \[0, 10\], got -1$"):
        podid.cwt(x, 1e-3, coi_factor=-1)
    with pytest.raises(ValueError, match=r"^threads: expected 1\.\.256, got 0$"):
        podid.cwt(x, 1e-3, threads=0)
    with pytest.raises(ValueError, match=r"^voices, fmin, fmax: expected at most 100000 frequencies"):
        podid.cwt(x, 1e-3, fmin=1e-300, fmax=100, voices=1024)
    with pytest.raises(ValueError, match=r"^voices, fmin, fmax: expected a finite ratio fmax / fmin"):
        podid.cwt(x, 1e-3, fmin=5e-324, fmax=100)
    # A step of 1e-200 s gave a float scalogram of zeros with the energy normalisation.
    with pytest.raises(ValueError,
                       match=r"step_s: expected a finite value between 1e-15 s and 1e15 s, got 1e-200"):
        podid.cwt(x, 1e-200, fmin=1e198, fmax=1e199, normalisation="energy", output="magnitude")


MEASURED_1S = str(SOURCE / "examples" / "measured_knl50_T1.0.csv")
MEASURED_01S = str(SOURCE / "tests" / "data" / "measured_knl50_T0.1.csv")
# The reference data's true knl is 50; issue 5's acceptance bound is 0.5 %.
KNL_TOLERANCE = 0.005


def test_identify_finds_the_true_knl():
    calls = []
    r = podid.identify(CASE, MEASURED_1S, objective="wavelet", start={"knl": 25.0},
                       progress=lambda done, total: calls.append(done))
    assert r["usable"], r["message"]
    assert abs(r.parameters["knl"] / 50.0 - 1) < KNL_TOLERANCE
    lo, hi = r.intervals["knl"]
    assert lo < r.parameters["knl"] < hi and r.standard_errors["knl"] > 0
    assert r.correlation.shape == (1, 1)
    assert calls == list(range(1, r["evaluations"] + 1))
    assert "Identification summary" in r["summary"]


def test_the_wavelet_term_takes_a_morse_wavelet():
    # MATLAB's default Morse wavelet (gamma 3, beta 20) in the IF term, as
    # `podid identify --wavelet morse`: knl within the same 0.5 %, and the
    # landscape's minimum at 50 on a 1-wide grid.
    r = podid.identify(CASE, MEASURED_1S, objective="wavelet", start={"knl": 25.0}, wavelet="morse")
    assert r["usable"], r["message"]
    assert abs(r.parameters["knl"] / 50.0 - 1) < KNL_TOLERANCE
    land = podid.landscape(CASE, MEASURED_1S, "knl", 40.0, 60.0, points=21, objectives=["wavelet"],
                           wavelet="morse", gamma=3.0, beta=20.0)
    assert land["metrics"]["wavelet"]["global_minimiser"] == 50.0
    # The keywords reach the objective: Morse's IF term is not Morlet's, nor
    # is the energy-normalised one (its ridge weights |W| by sqrt(s)).
    terms = [podid.Objective(CASE, MEASURED_1S, weightings=["wavelet"], **kw).evaluate({"knl": 45.0})["terms"]
             for kw in ({}, {"wavelet": "morse"}, {"normalisation": "energy"})]
    assert all(t["IF"] > 0 for t in terms)
    assert terms[0]["IF"] != terms[1]["IF"] and terms[0]["IF"] != terms[2]["IF"]
    with pytest.raises(ValueError, match="wavelet: expected one of morlet, morse"):
        podid.Objective(CASE, MEASURED_1S, weightings=["wavelet"], wavelet="mexhat")
    with pytest.raises(ValueError, match=r"^beta / gamma: expected <= 100, got 200"):
        podid.identify(CASE, MEASURED_1S, wavelet="morse", gamma=1.0, beta=200.0)
    with pytest.raises(ValueError, match=r"^omega0: expected >= 5, got 4"):
        podid.landscape(CASE, MEASURED_1S, "knl", 40.0, 60.0, points=3, omega0=4.0)
    with pytest.raises(ValueError, match="scale_convention: expected one of ridge, peak"):
        podid.Objective(CASE, MEASURED_1S, weightings=["wavelet"], scale_convention="matlab")
    with pytest.raises(ValueError, match="normalisation: expected one of amplitude, energy"):
        podid.identify(CASE, MEASURED_1S, normalisation="l2")


def test_one_objective_serves_several_weightings():
    both = podid.Objective(CASE, MEASURED_01S, weightings=["full", "time-free", "U,S:1,2"])
    e = both.evaluate({"knl": 40.0})
    assert not e["failed"]
    full = podid.Objective(CASE, MEASURED_01S, weightings=["full"]).evaluate({"knl": 40.0})
    assert e["values"]["full"] == full["values"]["full"]  # the same simulation, bit for bit
    t = e["terms"]
    assert e["values"]["time-free"] == pytest.approx(t["U"] + t["S"], rel=1e-15)
    assert e["values"]["U,S:1,2"] == pytest.approx(t["U"] + 2 * t["S"], rel=1e-15)


def test_ridge_threads_give_the_same_objective_and_are_checked():
    # 40 s at 5 kHz: 12,501 x 115 ridge cells, two blocks of the streamed
    # ridge, so ridge_threads=2 runs its pipeline; the values are the
    # one-thread values bit for bit (docs/wavelet.md, "Streamed ridge").
    longer = ["time.duration=40"]
    record = podid.simulate(CASE, set=longer, noise=False).sensors
    values = [podid.Objective(CASE, record, weightings=["wavelet"], set=longer, ridge_threads=t)
              .evaluate({"knl": 45.0}) for t in (1, 2)]
    assert not values[0]["failed"] and values[0]["terms"]["IF"] > 0
    assert values[1]["terms"]["IF"] == values[0]["terms"]["IF"]
    assert values[1]["values"]["wavelet"] == values[0]["values"]["wavelet"]
    with pytest.raises(ValueError, match="threads: expected 1..256"):
        podid.Objective(CASE, MEASURED_01S, weightings=["wavelet"], ridge_threads=0)


def test_keep_mean_compares_an_offset_the_default_pod_removes(tmp_path):
    # The record shifted by a constant: with the means removed (eq. 1) the
    # terms are those of the record itself, to the round-off of subtracting
    # a mean (1e-10 relative to the terms); with keep_mean the shift counts.
    data = np.loadtxt(MEASURED_01S, delimiter=",", skiprows=1)
    header = open(MEASURED_01S).readline().strip()
    data[:, 1:] += 1e-3
    shifted = tmp_path / "shifted.csv"
    np.savetxt(shifted, data, delimiter=",", header=header, comments="", fmt="%.15e")
    plain = podid.Objective(CASE, MEASURED_01S, weightings=["S,V"]).evaluate({"knl": 40.0})
    removed = podid.Objective(CASE, str(shifted), weightings=["S,V"]).evaluate({"knl": 40.0})
    kept = podid.Objective(CASE, str(shifted), weightings=["S,V"], keep_mean=True).evaluate({"knl": 40.0})
    assert removed["values"]["S,V"] == pytest.approx(plain["values"]["S,V"], rel=1e-10)
    assert kept["values"]["S,V"] > 10 * plain["values"]["S,V"]
    # identify and landscape take keep_mean too: their first point is the
    # Objective's value at the same parameters, from the same simulation.
    start = podid.Objective(CASE, str(shifted), weightings=["S,V"], keep_mean=True).evaluate()
    r = podid.identify(CASE, str(shifted), objective="S,V", keep_mean=True, max_evaluations=2)
    assert r["initial_objective"] == start["values"]["S,V"]
    g = podid.landscape(CASE, str(shifted), "knl", 40.0, 60.0, 2, objectives=["S,V"], keep_mean=True)
    assert g["values"]["S,V"][0] == kept["values"]["S,V"]


def test_failures_are_values_and_errors_are_exceptions():
    o = podid.Objective(CASE, MEASURED_01S, set=["initial.static_tip_force=0"])
    e = o.evaluate()
    assert e["failed"] and e["failure"] and math.isnan(e["values"]["full"])
    with pytest.raises(ValueError, match="knl"):
        podid.Objective(CASE, MEASURED_01S).evaluate({"no_such": 1.0})
    with pytest.raises(ValueError, match="wavelet"):  # 0.1 s is shorter than the cone at 10 Hz
        podid.Objective(CASE, MEASURED_01S, weightings=["wavelet"])


def test_landscape_and_a_progress_callback_that_raises():
    calls = []
    g = podid.landscape(CASE, MEASURED_01S, "knl", 0.0, 100.0, 11, objectives=["full", "time-free"],
                        progress=lambda d, t: calls.append((d, t)))
    assert len(calls) == 11 and calls[-1] == (11, 11)
    assert g["metrics"]["time-free"]["global_minimiser"] == 50.0
    assert np.all(np.isfinite(g["values"]["full"]))

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        podid.landscape(CASE, MEASURED_01S, "knl", 0.0, 100.0, 50, objectives=["full"], progress=stop)


def test_readme_example_script(tmp_path):
    import subprocess
    import sys
    env = dict(os.environ)
    out = subprocess.run([sys.executable, str(SOURCE / "python" / "examples" / "identify_readme.py")],
                         capture_output=True, text=True, env=env, check=True).stdout
    assert "knl = 50.1456" in out
    assert "wavelet    minima 1, minimiser 50" in out


def test_identify_stops_when_its_progress_callback_raises():
    def stop(done, total):
        raise RuntimeError("stopped by the user")

    with pytest.raises(RuntimeError, match="stopped by the user"):
        podid.identify(CASE, MEASURED_01S, objective="time-free", multistart=3, threads=2, progress=stop)


# A record simulated by podid itself at knl = 50, written with 17 digits (it
# reads back exactly) and compared at knl = 50: both sides are the same
# computation, so every term is round-off or exactly 0. Before the measured
# side was prepared as `podid identify` prepares it, the [data] filter reached
# only the simulated side (F = 1.6e-3 with a 31 Hz harmonic force) and a
# record starting at t = 0.5 s was compared with a simulation from t = 0,
# which reads the force file half a second early (F = 2.6).
SAME_RECORD_TOLERANCE = 1e-20


def test_the_measured_record_is_conditioned_and_timed_as_podid_identify_does(tmp_path):
    t = np.arange(0.0, 1.2, 1e-4)
    force = tmp_path / "force.csv"
    np.savetxt(force, np.column_stack([t, 20.0 * np.sin(2 * np.pi * (30.0 + 20.0 * t) * t)]), delimiter=",",
               header="t,N", comments="", fmt="%.17e")
    forced = ["initial.static_tip_force=0", 'force.0.type="file"', "force.0.node=6",
              "force.0.file=" + json.dumps(str(force)), 'force.0.column="N"', "time.start=0.5"]
    sim = podid.simulate(CASE, set=forced, noise=False)
    assert sim.completed, sim.message
    assert sim.sensors.time_s[0] == 0.5
    record = tmp_path / "from_half_a_second.csv"
    np.savetxt(record, np.column_stack([sim.sensors.time_s, sim.sensors.values]), delimiter=",",
               header="t," + ",".join(sim.sensors.channel_names), comments="", fmt="%.17e")
    case = forced[:-1]  # time.start comes from the record
    lowpass = ['data.filter="lowpass"', "data.cutoff=100"]
    for measured in (str(record), podid.read(str(record))):
        for extra in ([], lowpass):
            with pytest.warns(UserWarning, match="the record starts at t = 0.5 s"):
                f = podid.Objective(CASE, measured, weightings=["full"], set=case + extra)
            value = f.evaluate({"knl": 50.0})["values"]["full"]
            assert value <= SAME_RECORD_TOLERANCE, (type(measured), extra, value)
    with pytest.raises(ValueError, match="data.decimate: expected 1"):
        podid.Objective(CASE, str(record), set=case + ["data.decimate=2"])


def test_duplicate_weightings_are_refused():
    # Values come back in a dict by name: a second "full" replaced the first.
    with pytest.raises(ValueError, match='weightings: expected distinct names, got "full" twice'):
        podid.Objective(CASE, MEASURED_01S, weightings=["full", "full"])
    with pytest.raises(ValueError, match='got "wavelet" twice'):
        podid.landscape(CASE, MEASURED_01S, "knl", 40.0, 60.0, 3, objectives=["wavelet", "full", "wavelet"])


def test_a_bad_weighting_string_is_named_in_the_keywords_terms():
    # The library's parser named the CLI's --terms/--weights; here both are
    # halves of one weighting string.
    with pytest.raises(ValueError, match=r'^weightings: "U,S:1": weights: expected 2 weights \(one per term of terms\), got 1'):
        podid.Objective(CASE, MEASURED_01S, weightings=["U,S:1"])
    with pytest.raises(ValueError, match=r'^weightings: "U,W": terms: expected a list of U, S, V, IF, got "W"'):
        podid.Objective(CASE, MEASURED_01S, weightings=["U,W"])
    with pytest.raises(ValueError, match=r'^weightings: "U:-1": weights: expected non-negative numbers'):
        podid.landscape(CASE, MEASURED_01S, "knl", 40.0, 60.0, 3, objectives=["U:-1"])
