#!/usr/bin/env bash
# Build the wheel, install it into a fresh venv outside the repository (no GUI extra, so
# no Qt), and run the console script from a temporary folder on a bundled example:
# `tofradar examples --copy`, `validate`, `run --frames 2`; then check the HDF5 file.
# Usage: tools/check_wheel.sh [PYTHON]   (run from the repository root; `make check-wheel`)
set -euo pipefail

PYTHON=${1:-python3}
# A PYTHONPATH into the repository would make the fresh venv see the source tree (and its
# build metadata) instead of the installed wheel.
unset PYTHONPATH PYTHONHOME
REPO=$(pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/tofradar-wheel.XXXXXX")
SRC=$REPO
CLEAN=""
if git -C "$REPO" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    # Built from a copy of the working tree's files (tracked ones, and new ones git does not
    # ignore): an in-tree build writes build/ and tofradar.egg-info/ into the repository,
    # and `make test` runs this check beside the test suites, which import from there.
    SRC=$WORK/src
    mkdir -p "$SRC"
    git -C "$REPO" ls-files -z --cached --others --exclude-standard \
        | (cd "$REPO" && tar --null --ignore-failed-read -T - -cf -) | tar -xf - -C "$SRC"
else
    # No git: an in-tree build leaves build/ and tofradar.egg-info/ behind; remove them
    # unless they were there before, so that the repository stays as it was.
    for d in build tofradar.egg-info; do [ -e "$REPO/$d" ] || CLEAN="$CLEAN $REPO/$d"; done
fi
trap 'rm -rf "$WORK" $CLEAN' EXIT

step() { echo "check-wheel: $*"; }

step "building the wheel of $SRC into $WORK/dist"
"$PYTHON" -m pip wheel --no-deps -q -w "$WORK/dist" "$SRC"
WHEEL=$(ls "$WORK"/dist/tofradar-*.whl)
BUNDLED=$("$PYTHON" -c "import sys, zipfile; print(sum(n.startswith('simcore/_resources/') \
    for n in zipfile.ZipFile(sys.argv[1]).namelist()))" "$WHEEL")
step "wheel $(basename "$WHEEL") bundles $BUNDLED resource files"
if [ "$BUNDLED" -lt 2 ]; then step "FAILED: the wheel lacks the bundled resources"; exit 1; fi

step "creating a fresh venv in $WORK/venv and installing the wheel (dependencies from the index)"
"$PYTHON" -m venv "$WORK/venv"
"$WORK/venv/bin/python" -m pip install -q "$WHEEL"

cd "$WORK"
mkdir run && cd run
export PATH="$WORK/venv/bin:$PATH"
step "in $(pwd): tofradar --version; tofradar examples; tofradar examples --copy ex"
tofradar --version
tofradar examples
tofradar examples --copy ex
step "tofradar validate ex/wall.json"
tofradar validate ex/wall.json
step "tofradar run ex/wall.json --frames 2 --out x.h5"
tofradar run ex/wall.json --frames 2 --out x.h5 --quiet
step "tofradar generate: a spec with a bundled furniture mesh (sofa), then validate"
cat > spec.json <<'SPEC'
{"name": "wheel", "base": "wall", "room": {"x_m": [0.5, 4.5], "y_m": [-2.0, 2.0]},
 "furniture": [{"piece": "sofa", "count": [1, 1]}]}
SPEC
tofradar generate spec.json --count 1 --out gen --quiet
test -f gen/furniture/sofa.obj
tofradar validate gen/scene_00000.json
step "checking x.h5"
python - <<'EOF'
import sys

import h5py

with h5py.File("x.h5", "r") as f:
    groups = sorted(k for k in f if isinstance(f[k], h5py.Group))
    n_frames = int(f["meta"].attrs["n_frames"])
    print(f"check-wheel: x.h5 top-level groups {groups}, n_frames {n_frames}")
    missing = {"meta", "tof", "radar"} - set(groups)
    if missing or n_frames != 2:
        sys.exit(f"check-wheel: FAILED: missing groups {sorted(missing)} or n_frames != 2")
EOF
if "$WORK/venv/bin/python" -c "import PyQt6" 2>/dev/null; then
    step "FAILED: PyQt6 was installed without the [gui] extra"; exit 1
fi
step "tofradar gui without the [gui] extra says what to install"
if tofradar gui 2>gui.err; then step "FAILED: tofradar gui succeeded without Qt"; exit 1; fi
cat gui.err
grep -q "tofradar\[gui\]" gui.err
step "OK"
