#!/usr/bin/env bash
# The replay check, in a real browser: installs Debian's headless-capable Chromium if it
# is missing, then runs the ignored browser tests (crates/monoculus-cli/tests/browser.rs):
# generated replays are opened headless, stepped to a round, tick or frame, screenshotted,
# and checked for script errors, the time shown, and robots drawn where the positions
# file says. Every Chromium the tests start gets a profile folder under one scratch
# folder; whatever happened, any Chromium still running from it is stopped at the end and
# the folder removed. Runs locally as in CI (as root; Chromium runs with --no-sandbox).
# The tour notebook's check opens target/python-ci/tour.html, which scripts/python-ci.sh
# writes (run it first).
#
# Usage: scripts/browser-ci.sh
set -euo pipefail
cd "$(dirname "$0")/.."

log() { echo "browser-ci: $*" >&2; }

if ! command -v chromium >/dev/null; then
  log "installing chromium from Debian's packages"
  export DEBIAN_FRONTEND=noninteractive
  install() {
    apt-get update -qq &&
      apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null
  }
  install || { log "install failed, retrying once"; sleep 5; install; }
fi
log "$(chromium --version 2>/dev/null || echo 'chromium (version unknown)')"

SCRATCH=$(mktemp -d /tmp/monoculus-browser.XXXXXX)
cleanup() {
  # Chromium processes started by the tests carry the scratch folder in their
  # --user-data-dir; stop any that are left.
  pkill -f -- "--user-data-dir=$SCRATCH" 2>/dev/null || true
  sleep 1
  pkill -9 -f -- "--user-data-dir=$SCRATCH" 2>/dev/null || true
  rm -rf "$SCRATCH"
}
trap cleanup EXIT

export MONOCULUS_CHROMIUM
MONOCULUS_CHROMIUM=$(command -v chromium)
export MONOCULUS_BROWSER_TMP=$SCRATCH
export MONOCULUS_TOUR_HTML="$PWD/target/python-ci/tour.html"
if [[ ! -f $MONOCULUS_TOUR_HTML ]]; then
  log "no $MONOCULUS_TOUR_HTML: run scripts/python-ci.sh first (it executes and exports the tour notebook)"
  exit 1
fi
# The same build as `cargo test --workspace`: nothing is compiled again.
cargo test --workspace --test browser --test explore_browser -- --ignored --test-threads=1
log "passed"
