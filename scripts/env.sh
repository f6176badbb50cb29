# shellcheck shell=bash
# Shared by scripts/setup, scripts/run and the other project commands.
#
# Two Python environments, each in a cache directory outside the repository so
# fresh clones reuse them:
#   primary  Home Assistant 2026.10.4 on Python >= 3.14.2
#   floor    Home Assistant 2026.2.3 on Python 3.13 (the version hacs.json claims)
#   library  no Home Assistant, on the floor's Python: the library's own test run
#            (scripts/test_library installs pyplc into it from its folder)
# and a third beside the primary one, on its Python, for the smoke run on the newest
# Home Assistant release (scripts/develop_env.sh builds it: ensure_newest_env):
#   newest   the newest Home Assistant release, no test dependencies
#
# The primary interpreter is, in order: $PYTHON, python3.14 on PATH, a Python 3.14
# that uv provides, and (on a Debian/Ubuntu host where the user is root) a minimal
# Debian testing ("forky") root filesystem with python3.14, entered with a private
# mount namespace and chroot. tecoapi_exec hides which case applies.

set -euo pipefail

REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
CACHE_DIR="${TECOAPI_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/tecoapi-ha}"
ROOTFS="$CACHE_DIR/forky-root"
ROOTFS_VENV="/opt/tecoapi/venv-primary"
PRIMARY_MIN="3.14.2"
HOST_CA_BUNDLE="/etc/ssl/certs/ca-certificates.crt"

log() { printf '\033[1m==> %s\033[0m\n' "$*" >&2; }
die() { printf 'error: %s\n' "$*" >&2; exit 1; }

# retry WHAT CMD...: run CMD up to $TECOAPI_RETRIES times (default 3), waiting 10 s,
# then 20 s, between attempts: installs go through mirrors and proxies, and one
# dropped connection must not fail a run. errexit does not apply inside CMD (it runs
# as a condition), so CMD is a program, or a function that returns its failures.
retry() {
    local what="$1" attempt=1 attempts="${TECOAPI_RETRIES:-3}"
    shift
    until "$@"; do
        if ((attempt >= attempts)); then
            log "$what failed $attempt times"
            return 1
        fi
        log "$what failed (attempt $attempt of $attempts); trying again in $((attempt * 10)) s"
        sleep $((attempt * 10))
        attempt=$((attempt + 1))
    done
}

# version_ok PYTHON MIN [MAX_EXCLUSIVE]: the interpreter's version is in range.
version_ok() {
    "$1" - "$2" "${3:-99.0}" <<'PY' 2>/dev/null
import sys
low = tuple(int(p) for p in sys.argv[1].split("."))
high = tuple(int(p) for p in sys.argv[2].split("."))
sys.exit(0 if low <= sys.version_info[:3] and sys.version_info[:2] < high else 1)
PY
}

# Print "host:<python>" or "rootfs" for the primary target.
primary_mode() {
    if [[ -n "${PYTHON:-}" ]]; then
        version_ok "$PYTHON" "$PRIMARY_MIN" || die "\$PYTHON=$PYTHON is not Python >= $PRIMARY_MIN"
        echo "host:$PYTHON"; return
    fi
    local candidate
    candidate="$(command -v python3.14 || true)"
    if [[ -n "$candidate" ]] && version_ok "$candidate" "$PRIMARY_MIN"; then
        echo "host:$candidate"; return
    fi
    if command -v uv >/dev/null 2>&1; then
        candidate="$(uv python find 3.14 2>/dev/null || true)"
        if [[ -z "$candidate" ]] && uv python install 3.14 >/dev/null 2>&1; then
            candidate="$(uv python find 3.14 2>/dev/null || true)"
        fi
        if [[ -n "$candidate" ]] && version_ok "$candidate" "$PRIMARY_MIN"; then
            echo "host:$candidate"; return
        fi
    fi
    if [[ "$(id -u)" == 0 ]] && [[ -f /etc/debian_version ]]; then
        echo "rootfs"; return
    fi
    die "no Python >= $PRIMARY_MIN found: set PYTHON=/path/to/python3.14, or install python3.14 or uv"
}

floor_python() {
    local candidate candidates=("${PYTHON_FLOOR:-}" "$(command -v python3.13 || true)")
    if command -v pyenv >/dev/null 2>&1; then
        candidates+=("$(pyenv root)"/versions/3.13*/bin/python3.13)
    fi
    if command -v uv >/dev/null 2>&1; then
        candidates+=("$(uv python find 3.13 2>/dev/null || true)")
    fi
    for candidate in "${candidates[@]}"; do
        if [[ -n "$candidate" && -x "$candidate" ]] && version_ok "$candidate" "3.13.0" "3.14"; then
            echo "$candidate"; return
        fi
    done
    die "no Python 3.13 for the floor target: set PYTHON_FLOOR=/path/to/python3.13"
}

# Print the requirements of a dependency group of pyproject.toml, one a line.
group_requirements() {
    local python="$1" group="$2"
    "$python" - "$REPO_ROOT/pyproject.toml" "$group" <<'PY'
import sys, tomllib
with open(sys.argv[1], "rb") as f:
    print("\n".join(tomllib.load(f)["dependency-groups"][sys.argv[2]]))
PY
}

ensure_rootfs() {
    [[ -x "$ROOTFS/usr/bin/python3.14" ]] && return
    log "Creating a Debian testing root filesystem with python3.14 in $ROOTFS (about a minute)"
    if ! command -v debootstrap >/dev/null 2>&1; then
        retry "apt-get install debootstrap" _host_apt_install debootstrap \
            || die "apt-get could not install debootstrap"
    fi
    mkdir -p "$CACHE_DIR"
    retry "debootstrap" _debootstrap \
        || die "debootstrap failed, see $CACHE_DIR/debootstrap.log"
    mv "$ROOTFS.partial" "$ROOTFS"
}

# _host_apt_install PACKAGE...: install Debian packages on the host (the mirror may
# serve a snapshot whose Release file has expired; the signatures are still checked).
_host_apt_install() {
    local options=(-o Acquire::Check-Valid-Until=false -o Acquire::Retries=3)
    apt-get "${options[@]}" update -qq \
        && DEBIAN_FRONTEND=noninteractive apt-get "${options[@]}" install -y -qq "$@" >/dev/null
}

# _debootstrap: a minimal forky with python3.14 in $ROOTFS.partial, from scratch.
_debootstrap() {
    local script=/usr/share/debootstrap/scripts/forky
    [[ -e "$script" ]] || script=/usr/share/debootstrap/scripts/sid
    rm -rf "$ROOTFS.partial"
    debootstrap --variant=minbase \
        --include=python3.14,python3.14-venv,ca-certificates,curl,procps \
        forky "$ROOTFS.partial" http://deb.debian.org/debian "$script" >"$CACHE_DIR/debootstrap.log" 2>&1
}

# rootfs_exec CMD...: run CMD inside the root filesystem, in the current directory,
# with the repository bind-mounted at its own path and the primary venv first on PATH.
rootfs_exec() {
    cp /etc/resolv.conf "$ROOTFS/etc/resolv.conf"
    cp /etc/hosts "$ROOTFS/etc/hosts"
    [[ -f "$HOST_CA_BUNDLE" ]] && cp "$HOST_CA_BUNDLE" "$ROOTFS/etc/ssl/certs/ca-certificates.crt"
    local passthrough=() name
    for name in TERM CI COLUMNS PYTEST_ADDOPTS HYPOTHESIS_PROFILE $(compgen -e | grep -E '^TECOAPI_' || true); do
        [[ -n "${!name:-}" ]] && passthrough+=("$name=${!name}")
    done
    unshare --mount --fork --kill-child=TERM -- /bin/bash -c '
        set -e
        root="$1" repo="$2" workdir="$3"; shift 3
        mount --make-rprivate /
        mount --rbind /proc "$root/proc"
        mount --rbind /dev "$root/dev"
        mount --rbind /sys "$root/sys"
        mount --rbind /tmp "$root/tmp"
        mkdir -p "$root$repo"
        mount --bind "$repo" "$root$repo"
        exec chroot "$root" /bin/bash -c "cd \"\$0\" 2>/dev/null || cd \"\$1\"; shift; exec \"\$@\"" "$workdir" "$repo" "$@"
    ' rootfs "$ROOTFS" "$REPO_ROOT" "$PWD" \
        /usr/bin/env -i HOME=/root LANG=C.UTF-8 \
        PATH="$ROOTFS_VENV/bin:/usr/local/bin:/usr/bin:/bin" \
        VIRTUAL_ENV="$ROOTFS_VENV" \
        SSL_CERT_FILE=/etc/ssl/certs/ca-certificates.crt \
        PIP_CERT=/etc/ssl/certs/ca-certificates.crt \
        PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_DEFAULT_TIMEOUT=180 \
        ${passthrough[@]+"${passthrough[@]}"} \
        "$@"
}

# venv_dir TARGET: where the target's virtual environment lives, as seen by its python.
# The newest target lives beside the primary one, on the same Python.
venv_dir() {
    case "$1" in
        primary|newest)
            if [[ "$(primary_mode)" == rootfs ]]; then
                echo "${ROOTFS_VENV%-primary}-$1"
            else
                echo "$CACHE_DIR/venv-$1"
            fi ;;
        floor|library) echo "$CACHE_DIR/venv-$1" ;;
    esac
}

# tecoapi_exec TARGET CMD...: run CMD with TARGET's environment (venv bin first on PATH).
tecoapi_exec() {
    local target="$1"; shift
    local mode venv
    mode="$(primary_mode)"
    venv="$(venv_dir "$target")"
    if [[ "$target" != floor && "$target" != library && "$mode" == rootfs ]]; then
        ROOTFS_VENV="$venv" rootfs_exec "$@"
    else
        PATH="$venv/bin:$PATH" VIRTUAL_ENV="$venv" "$@"
    fi
}

# ensure_env TARGET: create or update TARGET's virtual environment when the pinned
# dependencies changed since it was built (a stamp file holds their hash).
ensure_env() {
    mkdir -p "$CACHE_DIR"
    # One builder at a time: parallel commands wait for the first to finish.
    exec {lock_fd}>"$CACHE_DIR/setup-$1.lock"
    flock "$lock_fd"
    _ensure_env_locked "$1"
    flock -u "$lock_fd"
    exec {lock_fd}>&-
}

_ensure_env_locked() {
    local target="$1" mode python venv host_venv reqs stamp_file want
    mode="$(primary_mode)"
    venv="$(venv_dir "$target")"
    host_venv="$venv"
    if [[ "$target" == primary && "$mode" == rootfs ]]; then
        ensure_rootfs
        host_venv="$ROOTFS$ROOTFS_VENV"
        python="/usr/bin/python3.14"
    elif [[ "$target" == primary ]]; then
        python="${mode#host:}"
    else
        python="$(floor_python)"
    fi
    local tomlpy=python3
    version_ok python3 3.11 || tomlpy="$(floor_python)"
    reqs="$(group_requirements "$tomlpy" "$target")"
    want="$(printf '%s\n%s\n' "$python" "$reqs" | sha256sum | cut -d' ' -f1)"
    stamp_file="$host_venv/.tecoapi-stamp"
    if [[ -f "$stamp_file" && "$(cat "$stamp_file")" == "$want" ]]; then
        return
    fi
    log "Installing the $target environment ($venv); the first time takes a few minutes"
    local pip_flags=(--quiet)
    if [[ "$target" == floor ]] && ! version_ok "$python" 3.13.2; then
        # Home Assistant 2026.2 asks for >= 3.13.2; its tests run on 3.13.0.
        pip_flags+=(--ignore-requires-python)
    fi
    mkdir -p "$CACHE_DIR"
    printf '%s\n' "$reqs" >"$CACHE_DIR/requirements-$target.txt"
    if [[ "$target" == primary && "$mode" == rootfs ]]; then
        cp "$CACHE_DIR/requirements-$target.txt" "$ROOTFS/tmp-requirements.txt"
        retry "pip install (the $target environment)" rootfs_exec /bin/bash -c "
            set -e
            [ -x $ROOTFS_VENV/bin/pip ] || /usr/bin/python3.14 -m venv --clear $ROOTFS_VENV
            $ROOTFS_VENV/bin/pip install ${pip_flags[*]} -r /tmp-requirements.txt" \
            || die "pip could not install the $target environment"
        rm -f "$ROOTFS/tmp-requirements.txt"
    else
        [[ -x "$venv/bin/pip" ]] || "$python" -m venv --clear "$venv"
        retry "pip install (the $target environment)" \
            "$venv/bin/pip" install "${pip_flags[@]}" -r "$CACHE_DIR/requirements-$target.txt" \
            2> >(grep -v "is ignored: it is neither a file nor a directory" >&2) \
            || die "pip could not install the $target environment"
    fi
    echo "$want" >"$stamp_file"
}
