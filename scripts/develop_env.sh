# shellcheck shell=bash
# Sourced after env.sh by scripts/develop and scripts/test --e2e: what a real Home
# Assistant and a real browser need in the primary environment beyond the test
# dependencies. Both functions are idempotent and return at once when nothing is missing.
#
#   ensure_home_assistant_runtime  the packages Home Assistant would pip-install on its
#       first start with the demo's configuration (it then runs with --skip-pip,
#       offline): the requirements of every integration it sets up, at Home Assistant's
#       own pins (tests/e2e/requirements.py). assist_pipeline's audio packages among
#       them build from source on Python 3.14 (a C++ compiler and the Python headers).
#       Also the programs and libraries integrations it always sets up look for on
#       their first start (ffmpeg for tts, libturbojpeg for camera): without them
#       each logs an ERROR.
#   ensure_browser  all that, plus Debian's Chromium (/usr/bin/chromium) and the
#       playwright package; Playwright's own browser download is not used.

PLAYWRIGHT_VERSION="1.65.2"

# _missing_requirements TARGET EXTRA...: print those of the packages above (and of the
# EXTRA requirements) that TARGET's environment lacks at their pinned version (the
# pins of its Home Assistant), space-separated.
_missing_requirements() {
    local target="$1"; shift
    tecoapi_exec "$target" python -m tests.e2e.requirements "$@" | tr '\n' ' '
}

# Debian packages that build assist_pipeline's audio packages on Python 3.14.
BUILD_PACKAGES=(g++ python3.14-dev)
# Debian packages Home Assistant's default integrations use at run time: ffmpeg (tts,
# through the ffmpeg integration) and libturbojpeg (camera snapshots).
RUNTIME_PACKAGES=(ffmpeg libturbojpeg0)

# _host_runtime_missing: print what of RUNTIME_PACKAGES a host-mode primary lacks.
_host_runtime_missing() {
    command -v ffmpeg >/dev/null 2>&1 || echo ffmpeg
    if ! /sbin/ldconfig -p 2>/dev/null | grep -q 'libturbojpeg\.so'; then
        echo libturbojpeg0
    fi
}

# _rootfs_missing PACKAGE...: print those of the Debian packages that are not fully
# installed in the root filesystem (an install cut short counts as missing).
_rootfs_missing() {
    awk -v wanted="$*" '
        BEGIN { count = split(wanted, names, " "); for (i = 1; i <= count; i++) missing[names[i]] = 1 }
        /^Package: / { package = $2 }
        /^Status: install ok installed$/ { delete missing[package] }
        END { for (name in missing) print name }
    ' "$ROOTFS/var/lib/dpkg/status"
}

# _rootfs_ensure PACKAGE...: install into the root filesystem those of the Debian
# packages it lacks, with apt, in one go. Mirrors may serve a snapshot whose Release
# file has passed its Valid-Until date; the signatures are still checked. A failed
# index download fails the update (--error-on=any) so that it is tried again.
_rootfs_ensure() {
    local missing
    read -r -a missing <<<"$(_rootfs_missing "$@" | tr '\n' ' ')"
    [[ ${#missing[@]} -eq 0 ]] && return
    log "Installing ${missing[*]} into the root filesystem with apt"
    retry "apt-get install ${missing[*]}" rootfs_exec /bin/bash -c '
        set -e
        export DEBIAN_FRONTEND=noninteractive PATH=/usr/sbin:/usr/bin:/sbin:/bin
        options=(-o Acquire::Check-Valid-Until=false -o Acquire::Retries=3
            -o DPkg::Lock::Timeout=300)
        dpkg --configure -a
        apt-get "${options[@]}" update -qq --error-on=any
        apt-get "${options[@]}" install -y -qq --no-install-recommends "$@" >/dev/null
    ' apt "${missing[@]}" || die "apt-get could not install ${missing[*]} into $ROOTFS"
}

# _install_runtime TARGET EXTRA...: what Home Assistant needs to run with the demo's
# configuration, in TARGET's environment (primary or newest).
_install_runtime() {
    local target="$1" listed missing host_missing
    shift
    if [[ "$(primary_mode)" == rootfs ]]; then
        _rootfs_ensure "${RUNTIME_PACKAGES[@]}"
    else
        host_missing="$(_host_runtime_missing | tr '\n' ' ')"
        [[ -z "${host_missing// /}" ]] \
            || die "Home Assistant's default integrations need ${host_missing% }: install it (apt-get install ${host_missing% })"
    fi
    listed="$(_missing_requirements "$target" "$@")"  # a failure here stops the script
    read -r -a missing <<<"$listed"
    [[ ${#missing[@]} -eq 0 ]] && return
    if [[ "$(primary_mode)" == rootfs ]]; then
        _rootfs_ensure "${BUILD_PACKAGES[@]}"
    fi
    log "Installing ${missing[*]} into the $target environment"
    retry "pip install ${missing[*]}" tecoapi_exec "$target" pip install --quiet "${missing[@]}" \
        || die "pip could not install ${missing[*]} (the audio packages need a C++ compiler and the Python 3.14 headers)"
}

_ensure_runtime_locked() {
    _install_runtime primary "$@"
}

# _with_lock FUNCTION ARG...: one setup at a time, as ensure_env does.
_with_lock() {
    mkdir -p "$CACHE_DIR"
    exec {develop_lock_fd}>"$CACHE_DIR/setup-develop.lock"
    flock "$develop_lock_fd"
    "$@"
    flock -u "$develop_lock_fd"
    exec {develop_lock_fd}>&-
}

ensure_home_assistant_runtime() {
    _with_lock _ensure_runtime_locked
}

_ensure_browser_locked() {
    if [[ "$(primary_mode)" == rootfs ]]; then
        # With the build packages: on a fresh machine one apt run instead of two.
        _rootfs_ensure chromium "${BUILD_PACKAGES[@]}"
    elif [[ ! -x /usr/bin/chromium ]]; then
        die "the browser test drives Debian's Chromium at /usr/bin/chromium: install it (apt-get install chromium)"
    fi
    _ensure_runtime_locked "playwright==$PLAYWRIGHT_VERSION"
}

ensure_browser() {
    _with_lock _ensure_browser_locked
}

# The smoke run on the newest Home Assistant release (scripts/smoke) has an environment
# of its own beside the primary one, on the same Python: the newest release that
# supports that Python (pip picks it; TECOAPI_NEWEST_HA=VERSION pins one), with the
# packages its first start with the demo's configuration would install, and nothing
# of the tests' (no pytest-homeassistant-custom-component: it pins older releases).
# pip keeps its cache, so a new release costs only what changed.

# _newest_release: print the newest Home Assistant release pip can install here.
_newest_release() {
    if [[ -n "${TECOAPI_NEWEST_HA:-}" ]]; then
        echo "$TECOAPI_NEWEST_HA"
        return
    fi
    tecoapi_exec newest pip index versions homeassistant 2>/dev/null \
        | sed -n 's/^homeassistant (\(.*\))$/\1/p'
}

# _installed_release: print the Home Assistant release the newest environment has.
_installed_release() {
    tecoapi_exec newest python -c \
        'import importlib.metadata as m; print(m.version("homeassistant"))' 2>/dev/null || true
}

_ensure_newest_locked() {
    local venv installed wanted
    venv="$(venv_dir newest)"
    if [[ "$(primary_mode)" == rootfs ]]; then
        ensure_rootfs
        rootfs_exec /bin/bash -c "[ -x $venv/bin/pip ] || /usr/bin/python3.14 -m venv --clear $venv" \
            || die "could not create $venv"
    else
        local python
        python="$(primary_mode)"
        [[ -x "$venv/bin/pip" ]] || "${python#host:}" -m venv --clear "$venv"
    fi
    installed="$(_installed_release)"
    wanted="$(_newest_release)"
    if [[ -z "$wanted" ]]; then
        [[ -n "$installed" ]] || die "pip could not find a Home Assistant release to install"
        log "pip could not tell the newest Home Assistant release; the smoke run keeps $installed"
        wanted="$installed"
    fi
    if [[ "$installed" != "$wanted" ]]; then
        log "Installing Home Assistant $wanted into $venv for the smoke run (the first time takes a few minutes)"
        retry "pip install homeassistant==$wanted" \
            tecoapi_exec newest pip install --quiet "homeassistant==$wanted" \
            || die "pip could not install Home Assistant $wanted"
    fi
    _install_runtime newest
    _primary_target_notice
}

# _primary_target_notice: say when pytest-homeassistant-custom-component has a newer
# release than the primary target pins: once one pins the newest Home Assistant
# release, that release becomes the primary target (pyproject.toml's primary group).
_primary_target_notice() {
    local package=pytest-homeassistant-custom-component pinned newest
    pinned="$(grep -o "$package==[0-9.]*" "$REPO_ROOT/pyproject.toml" | head -1)"
    newest="$(tecoapi_exec newest pip index versions "$package" 2>/dev/null \
        | sed -n "s/^$package (\(.*\))\$/\1/p")"
    if [[ -n "$newest" && "$package==$newest" != "$pinned" ]]; then
        log "$package $newest is out (the primary target pins ${pinned#*==}): if it pins the newest Home Assistant, make it the primary target"
    fi
}

# ensure_newest_env: the newest environment, ready for the smoke run. Its own lock:
# installing a new release takes minutes, and scripts/develop need not wait for it.
ensure_newest_env() {
    mkdir -p "$CACHE_DIR"
    exec {newest_lock_fd}>"$CACHE_DIR/setup-newest.lock"
    flock "$newest_lock_fd"
    _ensure_newest_locked
    flock -u "$newest_lock_fd"
    exec {newest_lock_fd}>&-
}
