#!/usr/bin/env bash
# One-command set-up for a fresh Debian/Ubuntu machine with Python 3.10+.
#   bash scripts/bootstrap.sh launch [ARGS...]  install, then open the explorer window
#   bash scripts/bootstrap.sh test  [PYTEST ARGS...]  install, then run ruff and the whole suite
# It creates .venv in the repository, installs system packages with apt-get when run as
# root (otherwise it prints the apt-get line to run), and never hides a failing step.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
mode="${1:-}"
shift || true
case "$mode" in
  launch|test) ;;
  *) echo "usage: bash scripts/bootstrap.sh launch|test [args...]" >&2; exit 2 ;;
esac

# System libraries: EGL + Mesa (software GL 4.5 through llvmpipe), Xvfb for window tests,
# a UTF-8 locale for the formula renderer, the X client libraries glfw loads.
apt_packages=(libegl1 libegl-mesa0 libgl1 libgl1-mesa-dri libglx-mesa0 xvfb xauth x11-utils
              libxrandr2 libxinerama1 libxcursor1 libxi6 libxxf86vm1 locales python3-venv)
# The test suite also opens the static site in a real browser (Debian's chromium, driven by
# chromium-driver): Playwright's own browser download is not used.
if [ "$mode" = test ]; then
  apt_packages+=(chromium chromium-driver)
fi
missing=()
for pkg in "${apt_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "ok installed" || missing+=("$pkg")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "bootstrap: installing system packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "bootstrap: these system packages are missing: ${missing[*]}" >&2
    echo "bootstrap: install them with:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
fi

python=${PYTHON:-python3}
"$python" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 10) else 1)' || {
  echo "bootstrap: Python 3.10 or newer is needed ($("$python" --version 2>&1))" >&2; exit 1; }
if [ ! -x .venv/bin/python ]; then
  "$python" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
if [ "$mode" = launch ]; then
  .venv/bin/python -m pip install -q -e .
  exec .venv/bin/lpv-explorer "$@"
fi

.venv/bin/python -m pip install -q -e ".[test,exr,truth]"
.venv/bin/ruff check .
.venv/bin/python -m mypy        # the modules [tool.mypy] in pyproject.toml names
# pytest exits 5 when it collected no test: that is a failure here, like any non-zero code.
exec .venv/bin/python -m pytest "$@"
