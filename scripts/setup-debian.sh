#!/usr/bin/env bash
# Installs every build, test and target-test dependency from Debian 12 packages.
# Idempotent: safe to run on a machine that already has them.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

# arm64 is needed for the cross-built target (libraries the firmware links on the board).
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  $SUDO dpkg --add-architecture arm64
fi

HOST_PKGS=(
  build-essential cmake ninja-build pkg-config git python3
  ccache                   # compiler cache: repeated CI builds on one machine recompile only what changed
  libeigen3-dev            # maths (header-only)
  libgpiod-dev             # discrete lines, libgpiod v1.6 C API
  libmodbus-dev            # supervisory link
  linux-libc-dev           # SocketCAN headers (linux/can.h, can/raw.h)
  libgtest-dev libgmock-dev googletest
  libbenchmark-dev         # amb-bench
  libtomlplusplus-dev      # board files (TOML v1.0, header-only)
  libcli11-dev             # command lines (header-only)
  nlohmann-json3-dev       # JSON (header-only)
  libfftw3-dev             # FFT
  libmatio-dev             # MATLAB v5 .mat reader for measured data
  zlib1g-dev               # inflating compressed .mat variables for the structure check
  libnlopt-cxx-dev         # maintained optimisers (local bounded polish, model updating)
  clang libclang-rt-14-dev # libFuzzer + ASan/UBSan runtimes for scripts/fuzz.sh
  can-utils mbpoll         # interop tools nobody here wrote
  g++-aarch64-linux-gnu    # cross toolchain for the Linux/ARM board
  qemu-user qemu-system-arm qemu-utils   # run aarch64 binaries / boot the ARM board
  cpio e2fsprogs kmod                    # initramfs and virtual disk for the target test
  lintian                  # Debian package checks (scripts/package.sh)
  chromium chromium-driver               # headless report rendering test
  libsqlite3-dev libpq-dev               # fleet store: SQLite (default) and PostgreSQL client (amb-host fleet)
  postgresql                             # fleet store test starts a local server (initdb/pg_ctl)
  slurm-wlm munge                        # envelope --slurm; its test starts a one-node cluster
)
ARM_PKGS=(
  libc6-dev:arm64 libstdc++-12-dev:arm64
  libgpiod-dev:arm64 libmodbus-dev:arm64 libfftw3-dev:arm64
  libgtest-dev:arm64 libtomlplusplus-dev:arm64
)

need_update=1
if [ "${AMB_SETUP_SKIP_UPDATE:-0}" = 1 ]; then need_update=0; fi
missing=()
for p in "${HOST_PKGS[@]}" "${ARM_PKGS[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all Debian packages present"
  exit 0
fi
echo "setup: installing ${#missing[@]} package(s): ${missing[*]}"
if [ $need_update = 1 ]; then $SUDO apt-get update -q; fi
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
