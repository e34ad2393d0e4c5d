#!/usr/bin/env bash
# Builds the Debian packages into dist/: amb-firmware (arm64, from the aarch64 cross build) and
# amb-host (amd64, from the host build), checks that every shared library the packaged
# binaries need is covered by the package's Depends, and runs lintian on both (errors fail).
#
# usage: bash scripts/package.sh [--revision N] [--no-lintian] [HOST_BUILD_DIR [ARM_BUILD_DIR]]
#   defaults: build and build-aarch64 (the directories of scripts/test.sh); a directory that is
#   not configured yet is configured as scripts/test.sh does. See docs/packaging.md.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
REV=1
LINTIAN=1
while [ $# -gt 0 ]; do
  case "$1" in
    --revision) REV=$2; shift 2;;
    --no-lintian) LINTIAN=0; shift;;
    -h|--help) sed -n '2,9p' "$0"; exit 0;;
    *) break;;
  esac
done
BUILD=$(realpath -m "${1:-$ROOT/build}")
BUILD_ARM=$(realpath -m "${2:-$ROOT/build-aarch64}")
DIST=$ROOT/dist
JOBS=${AMB_JOBS:-2}
export CCACHE_BASEDIR="$ROOT" CCACHE_NOHASHDIR=1
mkdir -p "$DIST"

[ -f "$BUILD/CMakeCache.txt" ] || cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DAMB_BUILD_BENCH=OFF
[ -f "$BUILD_ARM/CMakeCache.txt" ] || cmake -S . -B "$BUILD_ARM" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/aarch64-linux-gnu.cmake" -DAMB_BUILD_HOST_TOOLS=OFF -DAMB_BUILD_BENCH=OFF \
  "-DAMB_TEST_DIRS=firmware;linux;rt;plant" -DAMB_BUILD_PLANT=ON

# pack BUILD_DIR COMPONENT TARGETS...: build what the component installs, then cpack it.
pack() {
  local dir=$1 comp=$2; shift 2
  cmake --build "$dir" -j"$JOBS" --target "$@" amb_package_docs
  ( cd "$dir" && cpack -G DEB -D CPACK_DEBIAN_PACKAGE_RELEASE="$REV" -D CPACK_OUTPUT_FILE_PREFIX="$DIST" \
      -D "CPACK_COMPONENTS_ALL=$comp" -B "$dir/_cpack" ) | grep -v '^CPack: - Install\|^CPack: Create'
}
pack "$BUILD_ARM" firmware amb-firmware
pack "$BUILD" host amb-host amb-plant
VERSION=$(sed -n 's/^project(amb_supervisor VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
FW_DEB=$DIST/amb-firmware_${VERSION}-${REV}_arm64.deb
HOST_DEB=$DIST/amb-host_${VERSION}-${REV}_amd64.deb
FAIL=0

# Every NEEDED library of the packaged binaries must belong to a package named in Depends
# (dpkg -S on the multiarch install that the binary was linked against).
check_depends() {  # check_depends DEB LIBDIR
  local deb=$1 libdir=$2 x depends missing=""
  x=$(mktemp -d)
  dpkg-deb -x "$deb" "$x"
  depends=$(dpkg-deb -f "$deb" Depends)
  for bin in "$x"/usr/bin/*; do
    for lib in $(readelf -d "$bin" | sed -n 's/.*Shared library: \[\(.*\)\].*/\1/p'); do
      local owner
      owner=$(dpkg -S "$libdir/$lib" 2>/dev/null | head -1 | cut -d: -f1 || true)
      [ -n "$owner" ] || owner=$(dpkg -S "/lib/${libdir##*/}/$lib" 2>/dev/null | head -1 | cut -d: -f1 || true)
      if [ -z "$owner" ] || ! echo ", $depends" | grep -q ", $owner\( \|,\|$\)"; then
        missing="$missing $(basename "$bin"):$lib(${owner:-?})"
      fi
    done
  done
  rm -rf "$x"
  if [ -n "$missing" ]; then echo "package: $(basename "$deb"): NEEDED libraries not covered by Depends:$missing"; FAIL=1
  else echo "package: $(basename "$deb"): every NEEDED library is covered by Depends: $depends"; fi
}
check_depends "$FW_DEB" /usr/lib/aarch64-linux-gnu
check_depends "$HOST_DEB" /usr/lib/x86_64-linux-gnu

if [ $LINTIAN = 1 ]; then
  command -v lintian >/dev/null || { echo "package: lintian missing (scripts/setup-debian.sh installs it)"; exit 1; }
  for deb in "$FW_DEB" "$HOST_DEB"; do
    out=$(lintian --info --display-info "$deb" 2>&1 || true)
    echo "== lintian $(basename "$deb"): $(echo "$out" | grep -c '^E:') error(s), $(echo "$out" | grep -c '^W:') warning(s)"
    [ -n "$out" ] && echo "$out" | grep '^[EWI]:' | sed 's/^/  /'
    echo "$out" | grep -q '^E:' && FAIL=1
  done
fi
ls -l "$FW_DEB" "$HOST_DEB"
[ $FAIL = 0 ] && echo "package: OK" || { echo "package: FAILED"; exit 1; }
