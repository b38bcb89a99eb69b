"""What the Python transforms keep: band_limited (the CLI's --band-limited)
and max_memory_MB (--max-memory), against the full-rate transform and the
CLI's bounds. Run by ctest (python.pytest) with PYTHONPATH=<build>/python."""
import math

import numpy as np
import pytest

import podid

# Band-limited output is the full transform read every D-th sample, not an
# interpolation: equal to the band truncation (1e-12 of a filter's peak) and
# the rounding of two FFT lengths, as tests/wavelet/cwt_test.cpp's
# Cwt.BandLimitedModeIsTheDecimatedFullTransform holds it (1e-11 of max |W|).
DECIMATED_TOLERANCE = 1e-11
# |W| rounded once to float32: 2^-24 relative, and |W| in double (1e-16); the
# C++ test SinglePrecision.MagnitudeOutputIsTheRoundedComplexMagnitude holds
# it to the same 1e-7.
FLOAT_MAGNITUDE_RELATIVE = 1e-7
# A tone's IF from the phase derivative away from the ends: exact up to the
# band tolerance, as in test_podid.py.
TONE_IF_TOLERANCE_HZ = 1e-6


def chirp_and_tone(step, n):
    t = np.arange(n) * step
    return np.cos(2 * math.pi * (20.0 * t + 5.0 * t * t)) + 0.3 * np.cos(2 * math.pi * 70.0 * t)


def test_band_limited_cwt_is_the_full_transform_every_dth_sample():
    step = 2e-4
    x = chirp_and_tone(step, 5001)
    full = podid.cwt(x, step, padding="reflect")
    band = podid.cwt(x, step, padding="reflect", band_limited=True)
    assert full.decimation == 1 and band.decimation == 16  # 5 kHz, 10-120 Hz: as the C++ test
    d = band.decimation
    assert band.coefficients.shape == (313, len(full.frequencies_Hz))
    np.testing.assert_array_equal(band.time_s, full.time_s[::d])
    np.testing.assert_array_equal(band.frequencies_Hz, full.frequencies_Hz)
    np.testing.assert_array_equal(band.coi_frequency_Hz, full.coi_frequency_Hz[::d])
    scale = np.abs(full.coefficients).max()
    assert np.abs(band.coefficients - full.coefficients[::d]).max() <= DECIMATED_TOLERANCE * scale


def test_band_limited_ridges_and_synchrosqueeze_keep_the_if():
    step = 1e-3
    t = np.arange(4000) * step
    x = np.cos(2 * math.pi * 40.0 * t)
    middle = lambda tr: (tr.time_s > 1) & (tr.time_s < 3)
    track = podid.ridges(x, step, fmin=20, fmax=80, band_limited=True)[0]
    assert track.time_s[1] - track.time_s[0] > step  # decimated
    assert np.max(np.abs(track.frequency_Hz[middle(track)] - 40.0)) < TONE_IF_TOLERANCE_HZ
    squeezed = podid.synchrosqueeze(x, step, fmin=20, fmax=80, band_limited=True)
    full = podid.synchrosqueeze(x, step, fmin=20, fmax=80)
    d = squeezed.sst.decimation
    assert d > 1 and len(squeezed.sst.time_s) == len(full.sst.time_s[::d])
    (sq_track,) = squeezed.ridges()
    assert np.max(np.abs(sq_track.frequency_Hz[middle(sq_track)] - 40.0)) < TONE_IF_TOLERANCE_HZ


def test_max_memory_refuses_what_it_would_exceed_and_names_the_keyword():
    step = 1e-4
    x = np.cos(2 * math.pi * 50.0 * np.arange(100000) * step)
    # 10^5 times x 115 frequencies x 16 bytes: 184 MB of W, 186 MB with the FFTs'
    # buffers (the library's count).
    with pytest.raises(ValueError, match=r"at most 104857600 bytes \(max_memory_MB\), got \d+ bytes for 100000 output times x 115 "):
        podid.cwt(x, step, max_memory_MB=100)
    assert podid.cwt(x, step, max_memory_MB=100, band_limited=True).decimation > 1
    with pytest.raises(ValueError, match=r"max_memory_MB\)"):
        podid.ridges(x, step, max_memory_MB=100)
    # The synchrosqueezed transform takes 24 bytes a coefficient: W's share is 16/24.
    with pytest.raises(ValueError, match=r"at most 104857600 bytes .*\[max_memory_MB 150 x 16 / 24"):
        podid.synchrosqueeze(x, step, max_memory_MB=150)
    # The smallest limit: W's share of 1 MB is a budget (once refused as a bad option).
    with pytest.raises(ValueError, match=r"at most 699050\.6667 bytes .*\[max_memory_MB 1 x 16 / 24"):
        podid.synchrosqueeze(x, step, max_memory_MB=1)
    # The streamed ridge keeps about 1 byte a coefficient: 1 MB is too little here.
    with pytest.raises(ValueError, match=r"max_memory_MB\)"):
        podid.instantaneous_frequency(x, step, max_memory_MB=1)
    for bad in (0.5, 2.0**25, float("nan")):
        with pytest.raises(ValueError, match=r"^max_memory_MB: expected 1\.\.16777216 \(MB\), got "):
            podid.cwt(x, step, max_memory_MB=bad)


def test_magnitude_output_is_the_complex_magnitude_in_single_precision():
    step = 2e-4
    x = chirp_and_tone(step, 5001)
    full = podid.cwt(x, step)
    mag = podid.cwt(x, step, output="magnitude")
    assert mag.coefficients.size == 0 and mag.magnitude.dtype == np.float32
    assert mag.magnitude.shape == full.coefficients.shape
    expected = np.abs(full.coefficients)
    assert np.all(np.abs(mag.magnitude - expected) <= FLOAT_MAGNITUDE_RELATIVE * expected)
    assert full.magnitude.size == 0
    band = podid.cwt(x, step, output="magnitude", band_limited=True)
    assert band.magnitude.shape == (len(full.time_s[:: band.decimation]), len(full.frequencies_Hz))
    # A quarter of the bytes: 10^5 x 115 magnitudes (46 MB) fit 100 MB, where W does not.
    long = np.cos(2 * math.pi * 50.0 * np.arange(100000) * 1e-4)
    assert podid.cwt(long, 1e-4, max_memory_MB=100, output="magnitude").magnitude.shape == (100000, 115)
    with pytest.raises(ValueError, match="complex coefficients"):
        podid.inverse_cwt(mag)
    with pytest.raises(ValueError, match=r'^output: expected one of complex, magnitude, complex-float, got "float"'):
        podid.cwt(x, step, output="float")


def test_complex_float_output_is_the_complex_output_rounded_to_complex64():
    step = 2e-4
    x = chirp_and_tone(step, 5001)
    full = podid.cwt(x, step)
    single = podid.cwt(x, step, output="complex-float")
    assert single.coefficients.size == 0 and single.magnitude.size == 0
    assert single.coefficients_float.dtype == np.complex64
    # W computed in double and each part rounded once: numpy's own cast, bit for bit.
    assert np.array_equal(single.coefficients_float, full.coefficients.astype(np.complex64))
    assert full.coefficients_float.size == 0
    # Half the bytes: 10^5 x 115 coefficients (92 MB) fit 100 MB, where W (184 MB) does not.
    long = np.cos(2 * math.pi * 50.0 * np.arange(100000) * 1e-4)
    assert podid.cwt(long, 1e-4, max_memory_MB=100, output="complex-float").coefficients_float.shape == (
        100000,
        115,
    )
    with pytest.raises(ValueError, match=r"max_memory_MB"):
        podid.cwt(long, 1e-4, max_memory_MB=100)
    with pytest.raises(ValueError, match="complex coefficients"):
        podid.inverse_cwt(single)


def test_float_outputs_of_a_huge_signal_are_finite_in_units_of_coefficient_scale():
    # float32 ends at 3.4e38: a tone of 1e40 gave |W| = inf before. Beyond
    # 2^32 the float outputs carry a coefficient_scale (a power of 2).
    step = 2e-4
    x = 1e40 * chirp_and_tone(step, 2001)
    full = np.abs(podid.cwt(x, step).coefficients)
    for output, field in (("magnitude", "magnitude"), ("complex-float", "coefficients_float")):
        sg = podid.cwt(x, step, output=output)
        values = np.abs(getattr(sg, field).astype(np.complex128)) * sg.coefficient_scale
        assert sg.coefficient_scale > 1.0 and math.log2(sg.coefficient_scale).is_integer()
        assert np.all(np.isfinite(values))
        assert np.all(np.abs(values - full) <= 2 * FLOAT_MAGNITUDE_RELATIVE * full)
