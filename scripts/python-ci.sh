#!/usr/bin/env bash
# The Python package as a user gets it: the sdist (`maturin sdist`), the wheel built from
# that sdist (maturin, release), installed with pip into a fresh virtual environment. The
# Python tests and the tour notebook (examples/python/tour.ipynb, in a real Jupyter
# kernel) then run against the installed wheel, from outside the source tree, with no
# Rust toolchain on PATH. The executed notebook is exported as HTML to
# target/python-ci/tour.html for the browser check (scripts/browser-ci.sh).
#
# Usage: scripts/python-ci.sh [MONOCULUS_BIN] [WAIT_FOR_MOVERS_BIN]
#   the command-line binaries the tests compare with (default: target/debug's, which
#   `cargo test --workspace` builds).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BIN=$(realpath "${1:-target/debug/monoculus}")
WAIT_BIN=$(realpath "${2:-target/debug/wait-for-movers}")

log() { echo "python-ci: $*" >&2; }

WORK=$(mktemp -d /tmp/monoculus-python.XXXXXX)
trap 'rm -rf "$WORK"' EXIT

venv() {
  python3 -m venv "$1" 2>/dev/null || {
    rm -rf "$1"
    log "installing python3-venv from Debian's packages"
    apt-get update -q && apt-get install -y -q python3-venv
    python3 -m venv "$1"
  }
}

# Build: an sdist, and the wheel from it (so that the sdist is known to build).
venv "$WORK/build"
"$WORK/build/bin/pip" install -q "maturin>=1.5,<2"
(cd python && "$WORK/build/bin/maturin" sdist --out "$WORK/dist")
"$WORK/build/bin/pip" wheel -q --no-deps "$WORK"/dist/monoculus-*.tar.gz --wheel-dir "$WORK/dist"
wheel=$(ls "$WORK"/dist/monoculus-*.whl)
log "built $(basename "$wheel") from $(basename "$WORK"/dist/monoculus-*.tar.gz)"

# Install the wheel (with the plot extra) and the test tools into a fresh environment.
venv "$WORK/venv"
"$WORK/venv/bin/pip" install -q "$wheel[plot]" pytest nbclient nbconvert ipykernel

# From here no Rust toolchain is on PATH: the installed wheel is all there is.
path=""
IFS=: read -ra dirs <<< "$PATH"
for d in "${dirs[@]}"; do
  [[ -x "$d/cargo" || -x "$d/rustc" ]] && continue
  path="${path:+$path:}$d"
done
export PATH="$WORK/venv/bin:$path"
if command -v cargo >/dev/null || command -v rustc >/dev/null; then
  log "a Rust toolchain is still on PATH"; exit 1
fi
cd "$WORK"
python -c 'import monoculus, sys; assert "site-packages" in monoculus.__file__, monoculus.__file__'
mkdir -p "$ROOT/target/python-ci"
MONOCULUS_BIN="$BIN" MONOCULUS_WAIT_FOR_MOVERS_BIN="$WAIT_BIN" \
  MONOCULUS_TOUR_HTML="$ROOT/target/python-ci/tour.html" \
  python -m pytest -q -p no:cacheprovider "$ROOT/python/tests"
log "passed (wheel installed, no Rust toolchain on PATH, the tour notebook executed)"
