# What the scripts of this folder share. Sourced, never run:
#
#     set -euo pipefail
#     source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
#
# Sourcing it moves to the repository's root and sets `root` to it; then:
#   step TEXT...           prints a step's header
#   fail TEXT...           prints "<script>: FAILED: TEXT" on stderr and exits 1
#   need_apt PACKAGE       installs a Debian package (apt-get update first, once)
#   need_command CMD PKG   installs Debian package PKG when the command CMD is missing
#   target_dir             prints cargo's target directory as an absolute path
#                          (CARGO_TARGET_DIR, relative to the root, default target)
#   make_venv DIR          creates a Python virtual environment in DIR unless one
#                          is there (interpreter: PYTHON, default python3)
#   venv_pip DIR ARGS...   pip install ARGS into the virtual environment DIR, quietly

cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD

# The name failures are reported under: the script that sourced this file.
lib_script_name=$(basename "$0")

step() { printf '\n==> %s\n' "$*"; }

fail() {
    printf '\n%s: FAILED: %s\n' "$lib_script_name" "$*" >&2
    exit 1
}

lib_apt_updated=0
need_apt() {
    if [ "$lib_apt_updated" = 0 ]; then
        apt-get update -qq
        lib_apt_updated=1
    fi
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$1" >/dev/null
}

need_command() {
    command -v "$1" >/dev/null || need_apt "$2"
}

target_dir() {
    local target=${CARGO_TARGET_DIR:-target}
    case $target in
    /*) ;;
    *) target=$root/$target ;;
    esac
    printf '%s\n' "$target"
}

make_venv() {
    if [ ! -x "$1/bin/python" ]; then
        "${PYTHON:-python3}" -m venv "$1"
    fi
}

venv_pip() {
    local venv=$1
    shift
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "$@"
}
