#!/usr/bin/env bash
# End-to-end test of `podid pod FILE [--variable NAME] --json OUT` on measured-data
# files (docs/data-files.md), compared with an independent parse and POD in
# Python: scipy.io.loadmat for .mat, a few lines of struct unpacking for UFF 58b,
# numpy's SVD for the decomposition. Usage: bash tests/cli/pod_data_files.sh PODID
set -u
podid="$1"
data=tests/data/readers
. tests/support/cli.sh
cli_scratch

"$podid" pod "$data/testsystem_export.mat" --json "$out/ts.json" >/dev/null 2>"$out/ts.err" \
  || fail "pod testsystem_export.mat exited $?"
grep -q "podid: note: .*the label 'g' is the display unit" "$out/ts.err" || fail "no unit note"
"$podid" pod "$data/testsystem_export.mat" --variable Signal_2 --json "$out/ts2.json" >/dev/null 2>&1 \
  || fail "pod --variable Signal_2 exited $?"
"$podid" pod "$data/plain_struct.mat" --variable data --json "$out/plain.json" >/dev/null 2>&1 \
  || fail "pod plain_struct.mat exited $?"
"$podid" pod "$data/uff_four_accelerations_58b_le_single.uff" --json "$out/uff.json" >/dev/null 2>&1 \
  || fail "pod uff exited $?"
"$podid" pod "$data/uff_four_accelerations_58b_be_double.uff" --channels 4+Z,1+Z \
  --json "$out/uff2.json" >/dev/null 2>&1 || fail "pod uff --channels exited $?"

/usr/bin/python3 - "$out" "$data" <<'PY' || fail "JSON differs from the independent parse"
import json, struct, sys
import numpy as np
import scipy.io as sio

out, data = sys.argv[1], sys.argv[2]
ok = True
# Relative tolerance of singular values: LAPACK here and Eigen/podid's kernels
# differ in rounding only (well-separated singular values of O(10) data).
TOL = 1e-9

def check(name, got, channels, units, t, y):
    global ok
    y = y - y.mean(axis=0)  # podid removes the mean by default (eq. 1)
    s = np.linalg.svd(y.T, compute_uv=False)
    problems = []
    if got["channels"] != channels: problems.append(("channels", got["channels"], channels))
    if got["units"] != units: problems.append(("units", got["units"], units))
    if got["samples"] != len(t): problems.append(("samples", got["samples"], len(t)))
    if abs(got["start_s"] - t[0]) > 1e-12: problems.append(("start_s", got["start_s"], t[0]))
    step = (t[-1] - t[0]) / (len(t) - 1)
    if abs(got["step_s"] - step) > 1e-12 * step: problems.append(("step_s", got["step_s"], step))
    sv = np.array(got["singular_values"])
    if len(sv) != len(s) or np.max(np.abs(sv - s) / s[0]) > TOL:
        problems.append(("singular_values", list(sv), list(s)))
    for p in problems:
        print(name, "expected", p[0], p[2], "got", p[1], file=sys.stderr)
        ok = False

m = sio.loadmat(data + "/testsystem_export.mat", squeeze_me=True, struct_as_record=False)
for var, file in (("Signal_0", "ts.json"), ("Signal_2", "ts2.json")):
    sig = m[var]
    n = int(sig.x_values.number_of_values)
    t = sig.x_values.start_value + sig.x_values.increment * np.arange(n)
    y = np.atleast_2d(sig.y_values.values)
    if y.shape[0] != n: y = y.T
    names = [str(x) for x in np.atleast_1d(sig.function_record.name)]
    check(var, json.load(open(out + "/" + file)), names, ["m/s^2"] * y.shape[1], t, y)

d = sio.loadmat(data + "/plain_struct.mat", squeeze_me=True, struct_as_record=False)["data"]
y = np.column_stack([d.acc1, d.acc2, d.both.T])
check("plain", json.load(open(out + "/plain.json")), ["acc1", "acc2", "both1", "both2"], [""] * 4,
      d.time, y)

def read_58b(path):
    """Time responses of a UFF file: (name, unit, start, step, values) per data set 58b."""
    raw = open(path, "rb").read()
    sets, at = [], 0
    while True:
        at = raw.find(b"    -1", at)
        if at < 0: break
        lines_start = raw.index(b"\n", at) + 1
        if raw.find(b"\n", lines_start) < 0: break
        first = raw[lines_start:raw.index(b"\n", lines_start)].decode().split()
        if first[0] != "58b":
            at = lines_start
            continue
        order, nbytes = int(first[1]), int(first[4])
        pos, rec = raw.index(b"\n", lines_start) + 1, []
        for _ in range(11):
            end = raw.index(b"\n", pos)
            rec.append(raw[pos:end].decode("latin-1").rstrip("\r"))
            pos = end + 1
        ftype, node, direction = int(rec[5][0:5]), int(rec[5][41:51]), int(rec[5][51:55])
        dtype, count = int(rec[6][0:10]), int(rec[6][10:20])
        start, step = float(rec[6][30:43]), float(rec[6][43:56])
        fmt = ("<" if order == 1 else ">") + ("f" if dtype == 2 else "d") * count
        values = struct.unpack(fmt, raw[pos:pos + nbytes])
        if ftype == 1:
            dirs = {1: "+X", 2: "+Y", 3: "+Z", -1: "-X", -2: "-Y", -3: "-Z", 0: "S"}
            sets.append(("%d%s" % (node, dirs[direction]), rec[8][47:].strip(), start, step, values))
        at = pos + nbytes
    return sets

for file, name, order in (("uff_four_accelerations_58b_le_single.uff", "uff.json", None),
                          ("uff_four_accelerations_58b_be_double.uff", "uff2.json", ["4+Z", "1+Z"])):
    sets = read_58b(data + "/" + file)
    if order: sets = [next(s for s in sets if s[0] == n) for n in order]
    t = sets[0][2] + sets[0][3] * np.arange(len(sets[0][4]))
    y = np.column_stack([np.array(s[4]) for s in sets])
    check(file, json.load(open(out + "/" + name)), [s[0] for s in sets], [s[1] for s in sets], t, y)
sys.exit(0 if ok else 1)
PY

# The real F-16 export and the Silverbox file, when ../shared/realdata is there.
real="${PODID_REALDATA:-../shared/realdata}"
if [ -f "$real/testlab/F16_Data.mat" ] && [ -f "$real/silverbox/SNLS80mV.mat" ]; then
  "$podid" pod "$real/testlab/F16_Data.mat" --modes 2 --json "$out/f16.json" >/dev/null 2>&1 \
    || fail "pod F16_Data.mat exited $?"
  "$podid" pod "$real/silverbox/SNLS80mV.mat" --rate 610.3515625 --channels V1,V2 \
    --json "$out/sb.json" >/dev/null 2>&1 || fail "pod SNLS80mV.mat exited $?"
  /usr/bin/python3 - "$out" "$real" <<'PY' || fail "real files differ from scipy + numpy"
import json, sys
import numpy as np
import scipy.io as sio
out, real = sys.argv[1], sys.argv[2]
TOL = 1e-9  # relative, singular values (rounding of two SVD implementations)
s0 = sio.loadmat(real + "/testlab/F16_Data.mat", squeeze_me=True, struct_as_record=False)["Signal_0"]
y = s0.y_values.values
j = json.load(open(out + "/f16.json"))
names = [str(n) for n in s0.function_record.name]
sv = np.linalg.svd((y - y.mean(axis=0)).T, compute_uv=False)[:2]
assert j["channels"] == names, "channels"
assert j["units"] == ["m/s^2"] * 115, j["units"][:3]
assert j["samples"] == s0.x_values.number_of_values
assert j["start_s"] == s0.x_values.start_value and j["step_s"] == s0.x_values.increment
assert np.max(np.abs(np.array(j["singular_values"][:2]) - sv) / sv[0]) < TOL, (j["singular_values"], sv)
m = sio.loadmat(real + "/silverbox/SNLS80mV.mat")
y = np.column_stack([m["V1"].ravel(), m["V2"].ravel()])
j = json.load(open(out + "/sb.json"))
sv = np.linalg.svd((y - y.mean(axis=0)).T, compute_uv=False)
assert j["channels"] == ["V1", "V2"] and j["samples"] == 131072 and j["start_s"] == 0.0
assert abs(j["step_s"] - 1 / 610.3515625) < 1e-15
assert np.max(np.abs(np.array(j["singular_values"]) - sv) / sv[0]) < TOL, (j["singular_values"], sv)
PY
else
  echo "pod data files: ../shared/realdata absent, real files not checked"
fi

# Bad input: one line, exit 1.
"$podid" pod "$data/testsystem_export.mat" --variable nope --json "$out/x.json" 2>"$out/err" \
  && fail "unknown variable accepted"
grep -q "expected a variable 'nope' (variables: Signal_0, Signal_1, Signal_2), got none" "$out/err" \
  || fail "variable message: $(cat "$out/err")"
"$podid" pod "$data/uff_four_accelerations_58.uff" --channels 1+Z,9+X 2>"$out/err" && fail "bad channel"
grep -q 'expected a channel "9+X" (channels: 1+Z, 2-Y, 3+X, 4+Z), got none' "$out/err" \
  || fail "channel message: $(cat "$out/err")"
"$podid" pod "$data/uff_four_accelerations_58.uff" --rate 0 2>"$out/err" && fail "--rate 0 accepted"
grep -q "expected a finite sampling rate > 0 Hz with a finite step 1 / rate, got 0" "$out/err" ||
  fail "rate message: $(cat "$out/err")"
# A subnormal step has an infinite rate (fs was printed as inf).
"$podid" pod "$data/uff_four_accelerations_58.uff" --step 1e-320 2>"$out/err" && fail "--step 1e-320 accepted"
grep -q -- "--step: expected a finite sampling step > 0 s with a finite rate 1 / step, got 9.999888672e-321" \
  "$out/err" || fail "step message: $(cat "$out/err")"
echo "pod data files: ok"
