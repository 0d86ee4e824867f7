#!/usr/bin/env bash
# Issue 43's "done when": a new fixed-arity constraint type touches at most 3 files outside tests and docs (its
# header, its kernel if any, the list) and goes through every pass with no other edit.
#
# Usage: check_new_type.sh SOURCE_DIR WORK_DIR [COMPILER_LAUNCHER]
#
# 1. Copies SOURCE_DIR's files (git ls-files: the tracked ones as they are in the work tree, plus untracked ones not
#    ignored) to WORK_DIR/src, commits them there, adds tests/new_type/leash.hpp as
#    engine/include/pbd/constraints/leash.hpp and one entry in BuiltinConstraintTypes (sed), and checks with
#    `git diff --stat` that at most 3 files changed outside tests/ and docs/.
# 2. Builds the copy (Debug at -O0, with clang when there is one, -j 2): the engine, io, the pbd program, the Python
#    module and new_type_tests.
# 3. Runs new_type_tests (the list-walking tests of tests/io with the leash in the list: checks, every solver,
#    validate(), its metric and unit, the describe round trip, removal; and the leash's physics against closed
#    forms), `pbd run` on scenes with a "leashes" key (the summary names it; the same hash on 1 and 2 threads, and
#    for independent leashes serial = serial-colored), a bad leash in a scene and in a Python call (the same
#    message, the scene's naming its key), `pbd study` (the leash's error in mm, its label and unit in the report)
#    and the Python bindings (add_leash, leash_violation, constraint_violations).
set -euo pipefail
src=$1
work=$2
launcher=${3:-}
fail() { echo "check_new_type.sh: FAIL: $*" >&2; exit 1; }
step() { echo "== $* ($(date -u +%H:%M:%S))"; }

step "copy the tree"
rm -rf "$work"
mkdir -p "$work/src"
(cd "$src" && git ls-files -z --cached --others --exclude-standard | while IFS= read -r -d '' f; do
  [ -e "$f" ] && printf '%s\0' "$f"; done | tar --null -T - -cf -) | tar -C "$work/src" -xf -
cd "$work/src"
git init -q .
git add -A
git -c user.name=check -c user.email=check@localhost commit -q -m "the tree as given"

step "add the leash: its header and one entry in the list"
cp tests/new_type/leash.hpp engine/include/pbd/constraints/leash.hpp
list=engine/include/pbd/constraint_types.hpp
sed -i 's|#include "pbd/constraints/stretch.hpp"|&\n#include "pbd/constraints/leash.hpp"|' "$list"
# After the list's last entry, whichever type that is: the one line of the file that ends in "<Real>>;".
sed -i 's|\(Constraint<Real>\)>;$|\1,\n               LeashConstraint<Real>>;|' "$list"
grep -q "LeashConstraint<Real>>;" "$list" || fail "the sed did not find the end of BuiltinConstraintTypes in $list"
git add -A
git diff --cached --stat
changed=$(git diff --cached --name-only | grep -v -e '^tests/' -e '^docs/' || true)
echo "files changed outside tests/ and docs/:"; echo "$changed"
count=$(printf '%s\n' "$changed" | grep -c . || true)
[ "$count" -le 3 ] || fail "$count files changed outside tests/ and docs/ (at most 3: header, kernel, list)"
[ "$count" -eq 2 ] || fail "expected exactly the header and the list, got $count files"

# Debug at -O0 with clang when the machine has it: the engine's assertions watch the leash go through every pass, and
# the copy (this test is a CI build of its own) compiles faster than with g++ at -O1 (clang is quicker on the engine's
# template-heavy files); what it runs is small, so -O0 is fast enough. Without clang, the default compiler at -O0.
cxx=$(command -v clang++ || true)
step "build the copy (Debug at -O0, ${cxx:-the default compiler}, -j 2)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O0" -DPBD_BUILD_BENCHMARKS=OFF -DPBD_BUILD_TESTS=ON \
  -DPBD_NEW_TYPE_INNER=ON ${cxx:+-DCMAKE_CXX_COMPILER=$cxx} ${launcher:+-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher} \
  > build.log 2>&1 || { cat build.log; fail "configure"; }
cmake --build build -j 2 --target new_type_tests pbd pbd_python >> build.log 2>&1 || { tail -50 build.log; fail "build"; }
pbd=$work/src/build/cli/pbd

step "new_type_tests: the list-walking tests with the leash, and the leash's physics"
build/tests/new_type/new_type_tests --gtest_brief=1 || fail "new_type_tests"

step "pbd run: the summary names the leash; the hashes"
mkdir -p scenes_t
cat > scenes_t/leashed.json <<'JSON'
{"name": "leashed", "dt": 0.01, "iterations": 4, "steps": 100, "primary_error": "leash",
 "bodies": [{"type": "particles", "positions": [[0,0,1],[1,0,1],[2,0,1],[3,0,1]], "mass": 1.0,
             "leashes": {"particles": [0, 1, 2, 3], "length": 0.5}}]}
JSON
cat > scenes_t/rope_leash.json <<'JSON'
{"name": "rope_leash", "dt": 0.01, "iterations": 8, "steps": 60,
 "bodies": [{"type": "rope", "particles": 30, "length": 1.5, "stretch": {"stiffness": 1.0},
             "leashes": {"particles": [29], "length": 0.4}}]}
JSON
out=$("$pbd" run scenes_t/leashed.json --solver serial --threads 1)
echo "$out" | head -1
# The types a mesh makes come first (stretch, bending, area, ..., in the list's order), then volume and the listed ones.
echo "$out" | head -1 | grep -q "constraints: 0 stretch, 0 bending, 0 area, .*0 volume, 0 anchor, 0 tether, .*4 leash$" \
  || fail "pbd run's summary does not name the leashes: $(echo "$out" | head -1)"
hash_of() { "$pbd" run "$@" | sed -n 's/^state hash: //p'; }
serial=$(hash_of scenes_t/leashed.json --solver serial --threads 1)
# serial-colored runs on one thread (pbd refuses --threads 2 with it); colored on 1 and 2.
for run in "serial-colored 1" "colored 1" "colored 2"; do
  read -r solver threads <<<"$run"
  h=$(hash_of scenes_t/leashed.json --solver "$solver" --threads "$threads")
  [ "$h" = "$serial" ] || fail "independent leashes: $solver on $threads threads $h, serial $serial"
done
echo "independent leashes: serial = serial-colored = colored on 1 and 2 threads ($serial)"
for solver in colored jacobi block; do
  one=$(hash_of scenes_t/rope_leash.json --solver $solver --threads 1)
  two=$(hash_of scenes_t/rope_leash.json --solver $solver --threads 2)
  [ "$one" = "$two" ] || fail "rope with a leash: $solver $one on 1 thread, $two on 2"
  echo "rope with a leash, $solver: $one on 1 and 2 threads"
done

step "a bad leash in a scene and in a Python call: the same message"
sed 's/"length": 0.5/"length": -1/' scenes_t/leashed.json > scenes_t/bad.json
if scene_error=$("$pbd" run scenes_t/bad.json 2>&1); then fail "a leash of length -1 was accepted"; fi
echo "$scene_error"
echo "$scene_error" | grep -q "/bodies/0/leashes/particles/0: add_leash: leash 0: length must be finite and >= 0, got -1" \
  || fail "the scene's error does not name the key and the engine's check"
export PYTHONPATH=$work/src/build/python
api_error=$(/usr/bin/python3 -c '
import pbd
w = pbd.World()
w.add_particle((0, 0, 1), 1.0)
s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
try:
    w.add_leash(0, s, length=-1.0)
except pbd.Error as e:
    print(e)
')
echo "$api_error"
[ "$api_error" = "add_leash: leash 0: length must be finite and >= 0, got -1" ] || fail "the API's message: $api_error"
echo "$scene_error" | grep -qF "$api_error" || fail "the scene's message differs from the API's"

step "pbd study: the leash's error with its unit"
"$pbd" study --quick --scene scenes_t/leashed.json --solvers serial,colored --threads 1 --budgets 2 \
  --json study.json --format csv > study.csv
/usr/bin/python3 - <<'PY' || fail "pbd study's report"
import json
doc = json.load(open("study.json"))
scene = doc["scenes"][0]
assert scene["primary_error"] == "leash_mm", scene
assert "leash_mm" in scene["measures"], scene
assert doc["measures"]["leash_mm"] == {"type": "leash", "label": "leash overstretch", "unit": "mm"}, doc["measures"]
for r in doc["records"]:
    assert "leash_mm" in r["errors"], r["errors"]
    assert r["errors"]["leash_mm"]["rms"] == r["primary_error"]
print("pbd study: leash_mm in", len(doc["records"]), "records; measures:", doc["measures"]["leash_mm"])
PY
grep -q "leash_mm_rms" study.csv || fail "the CSV has no leash_mm column"

step "Python: add_leash, leash_violation, constraint_violations, build_world of the scene"
/usr/bin/python3 - <<'PY' || fail "the Python bindings"
import pbd
w = pbd.WorldDouble()
w.add_particle((0, 0, 1), 1.0)
s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
assert w.add_leash(0, s, length=0.5) == 0
for _ in range(240):
    w.step()
z = w.positions()[0, 2]
assert abs(z - 0.5) < 1e-9, z                        # hangs L = 0.5 m below its fixed point (0, 0, 1)
v = pbd.leash_violation(w)
assert v.count == 1 and v.max < 1e-9, v
(named,) = pbd.constraint_violations(w)
assert (named.type, named.measure, named.unit, named.scale) == ("leash", "leash_mm", "mm", 1000.0), named.measure
assert "length" in pbd.World.add_leash.__doc__ and "target" in pbd.World.add_leash.__doc__
scene = pbd.load_scene("scenes_t/leashed.json")
f = pbd.build_world(scene)
assert f.num_constraints() == 4
f.validate()
print("python: z =", z, "violation", v, "measure", named.measure, named.unit)
PY
step "done: the leash went through every pass"
