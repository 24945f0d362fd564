#!/bin/sh
# Build the standalone game inside a Debian 11 root (glibc 2.31), so the folder runs on
# Debian 11+, Ubuntu 20.04+, RHEL 9 and anything else with glibc 2.31 or newer: a program
# needs a C library at least as new as the one it was linked against, and the build
# machine's Python is linked against its own.
#
#   sudo packaging/build-debian11.sh [--root DIR] [--dist DIR] [--no-archive]
#
# Needs root (debootstrap, chroot, mount), debootstrap and the network to Debian's mirror
# and the Python package index. What it does, each step skipped when already done:
#   1. debootstrap a minimal Debian 11 into DIR (default /var/cache/across-dimensions/debian11)
#      with a compiler, the libraries Python builds against, and Mesa for offscreen OpenGL;
#   2. build CPython 3.11 there from Debian's source of it (Debian 11 ships 3.9, the game
#      needs 3.11), installed in /opt/python3.11 with no search path of its own;
#   3. install the game from this checkout with its editor and standalone extras into
#      /opt/venv, at the versions this checkout's .venv has when there is one (the tested ones);
#   4. run `python -m across_dimensions.app.freeze` there, and copy dist/ out to --dist
#      (default dist/ in this checkout).
set -eu

here=$(cd "$(dirname "$0")/.." && pwd)
root=/var/cache/across-dimensions/debian11
dist=$here/dist
freeze_args=
while [ $# -gt 0 ]; do
    case $1 in
        --root) root=$2; shift 2 ;;
        --dist) dist=$2; shift 2 ;;
        --no-archive) freeze_args=--no-archive; shift ;;
        -h|--help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "build-debian11.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
done
if [ "$(id -u)" != 0 ] || ! command -v debootstrap >/dev/null; then
    echo "build-debian11.sh: needs root and debootstrap (apt-get install debootstrap)" >&2
    exit 2
fi

# Debian's mirror as this machine's apt knows it (a deb822 URIs: line or a one-line entry).
mirror=$(cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources 2>/dev/null |
    sed -n -e 's|^URIs:[[:space:]]*\([^[:space:]]*/debian\)/*$|\1|p' -e 's|^deb[[:space:]]\{1,\}\(\[[^]]*\][[:space:]]*\)\{0,1\}\([^[:space:]]*/debian\)/*[[:space:]].*|\2|p' |
    head -n 1)
mirror=${mirror:-http://deb.debian.org/debian}

# Python's build needs: compiler, zlib, bz2, lzma, ffi (ctypes). Mesa: the build compiles the
# renderer's kernels through the offscreen demo. binutils: strip.
packages=gcc,make,libc6-dev,binutils,xz-utils,ca-certificates,zlib1g-dev,libbz2-dev,liblzma-dev,libffi-dev,libssl-dev
packages=$packages,libegl1,libgl1,libgl1-mesa-dri,libx11-6
if [ ! -f "$root/.across-dimensions-root" ] || [ "$(cat "$root/.across-dimensions-root")" != "$packages" ]; then
    echo "== debootstrap Debian 11 into $root (from $mirror)"
    rm -rf "$root"
    mkdir -p "$root"
    # Exit 75 (EX_TEMPFAIL) when Debian's mirror cannot be reached, so CI can tell a missing
    # network from a broken build.
    if ! debootstrap --variant=minbase --include="$packages" bullseye "$root" "$mirror"; then
        echo "build-debian11.sh: debootstrap from $mirror failed (is Debian's mirror reachable?)" >&2
        rm -rf "$root"
        exit 75
    fi
    echo "$packages" > "$root/.across-dimensions-root"
fi

cleanup() {
    umount "$root/proc" 2>/dev/null || true
}
trap cleanup EXIT INT TERM
mount -t proc proc "$root/proc"
cp /etc/resolv.conf "$root/etc/resolv.conf"
# The host's certificate authorities: the package index may be reached through a proxy
# that only they trust.
cp /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/host-ca.crt" 2>/dev/null || true

run() {
    chroot "$root" env -i PATH=/opt/venv/bin:/usr/bin:/bin HOME=/root LANG=C.UTF-8 \
        LD_LIBRARY_PATH=/opt/python3.11/lib PIP_CERT=/etc/ssl/host-ca.crt PIP_DISABLE_PIP_VERSION_CHECK=1 \
        ${http_proxy:+http_proxy=$http_proxy} ${https_proxy:+https_proxy=$https_proxy} \
        ${HTTP_PROXY:+HTTP_PROXY=$HTTP_PROXY} ${HTTPS_PROXY:+HTTPS_PROXY=$HTTPS_PROXY} "$@"
}
[ -s "$root/etc/ssl/host-ca.crt" ] || run sh -c 'ln -sf /etc/ssl/certs/ca-certificates.crt /etc/ssl/host-ca.crt'

if [ ! -x "$root/opt/python3.11/bin/python3.11" ]; then
    echo "== CPython 3.11 from Debian's source (a few minutes)"
    echo "deb-src $mirror bookworm main" > "$root/etc/apt/sources.list.d/python-source.list"
    run sh -c 'apt-get update -q >/dev/null && mkdir -p /src/python && cd /src/python && apt-get source -q --download-only python3.11 >/dev/null'
    run sh -c 'set -e; cd /src/python; rm -rf Python-*/; tar xzf python3.11_*.orig.tar.gz; cd Python-3.11*/
        ./configure -q --prefix=/opt/python3.11 --enable-shared
        make -s -j"$(nproc)" >/dev/null 2>&1
        make -s altinstall >/dev/null 2>&1'
    run /opt/python3.11/bin/python3.11 -c "import ctypes, lzma, bz2, zlib"
fi

echo "== the game and its extras into /opt/venv"
rm -rf "$root/src/across-dimensions"
mkdir -p "$root/src/across-dimensions"
(cd "$here" && tar --exclude=./.git --exclude=./.venv --exclude=./build --exclude=./dist \
    --exclude='./.numba_cache*' --exclude='*/__pycache__' -cf - .) | tar -C "$root/src/across-dimensions" -xf -
: > "$root/src/constraints.txt"
if [ -x "$here/.venv/bin/python" ]; then
    "$here/.venv/bin/python" -m pip freeze --exclude-editable 2>/dev/null | grep '==' > "$root/src/constraints.txt" || true
fi
[ -x "$root/opt/venv/bin/python" ] || run /opt/python3.11/bin/python3.11 -m venv /opt/venv
run sh -c 'cd /src/across-dimensions && pip install -q -c /src/constraints.txt -e ".[editor,standalone]"'

echo "== freeze"
run sh -c "cd /src/across-dimensions && NUMBA_CACHE_DIR=/src/numba-cache python -m across_dimensions.app.freeze \
    --dist /src/dist --work /src/build $freeze_args"
mkdir -p "$dist"
rm -rf "$dist/across-dimensions"
cp -a "$root/src/dist/." "$dist/"
echo "== built in Debian 11 (glibc 2.31): $dist"
