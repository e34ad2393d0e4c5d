#!/usr/bin/env bash
# Target test: the cross-built aarch64 amb-firmware, installed from its Debian package, and
# amb-plant on an emulated ARM board.
#   Debian's PREEMPT_RT arm64 kernel (extracted from its package, never installed on the host)
#   booted by qemu-system-aarch64 -M virt (TCG, cortex-a57) with an initramfs built here:
#   busybox-static:arm64, can-utils:arm64, the binaries and their arm64 shared libraries, the
#   kernel modules they need. Field bus on vcan0, discrete lines on the virt PL061
#   (/dev/gpiochip0), storage on an ext4 virtual disk, Modbus TCP forwarded to 127.0.0.1.
# The host-built amb-host fetches a drop event and writes a wear record back; the board is
# restarted and must still hold the record. mbpoll reads the register map; candump/cansend
# see and inject field-bus frames. See docs/target-test.md.
# The firmware comes from the amb-firmware .deb (cpack in ARM_BUILD, packaging/): unpacked into
# the image (dpkg-deb -x) and started by the guest's init the way its systemd unit says
# (EnvironmentFile, LimitRTPRIO, LimitMEMLOCK, CPUAffinity, ExecStart); /proc must show the loop
# thread SCHED_FIFO and the memory locked. The second boot runs an upgraded package (a newer
# Debian revision) on the same data disk: the wear record and the events must be byte-identical.
# See docs/packaging.md.
#
# usage: bash tests/target/run-target-test.sh HOST_BUILD_DIR ARM_BUILD_DIR
set -uo pipefail
HOST_BUILD=$(cd "${1:?usage: run-target-test.sh HOST_BUILD_DIR ARM_BUILD_DIR}" && pwd)
ARM_BUILD=$(cd "${2:?usage: run-target-test.sh HOST_BUILD_DIR ARM_BUILD_DIR}" && pwd)
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CACHE=${AMB_TARGET_CACHE:-$HOST_BUILD/target-cache}
WORK=$(mktemp -d /tmp/amb-target.XXXXXX)
T_START=$(date +%s)
QEMU_PID=""
FAILS=0
PASSES=0

pass() { echo "PASS: $*"; PASSES=$((PASSES + 1)); }
fail() { echo "FAIL: $*"; FAILS=$((FAILS + 1)); }
die() { fail "$*"; finish; }
cleanup() {
  if [ -n "$QEMU_PID" ] && kill -0 "$QEMU_PID" 2>/dev/null; then kill "$QEMU_PID" 2>/dev/null; sleep 1; kill -9 "$QEMU_PID" 2>/dev/null; fi
  exec 3>&- 2>/dev/null
  [ "${AMB_TARGET_KEEP:-0}" = 1 ] || rm -rf "$WORK"
}
finish() {
  cleanup
  trap - EXIT
  echo "target test: $PASSES passed, $FAILS failed ($(( $(date +%s) - T_START )) s)"
  [ "$FAILS" -eq 0 ] && [ "$PASSES" -gt 0 ] && exit 0
  exit 1
}
trap finish EXIT
trap 'echo "FAIL: interrupted"; FAILS=$((FAILS + 1)); exit 1' INT TERM

FW=$ARM_BUILD/firmware/amb-firmware
PLANT=$ARM_BUILD/host-tools/amb-plant
HOST=$HOST_BUILD/host-tools/amb-host
for f in "$FW" "$PLANT" "$HOST"; do [ -x "$f" ] || die "missing $f (build amb-firmware and amb-plant for aarch64 with -DAMB_BUILD_PLANT=ON, amb-host for the host)"; done
for t in qemu-system-aarch64 mkfs.ext4 cpio mbpoll python3 readelf dpkg-deb apt-get cpack; do
  command -v $t >/dev/null || die "missing tool $t (scripts/setup-debian.sh installs it)"
done
readelf -h "$FW" 2>/dev/null | grep -q AArch64 || die "$FW is not an aarch64 binary"

# ---- kernel, busybox, can-utils: Debian arm64 packages, downloaded once into the cache ----------
mkdir -p "$CACHE"
fetch_pkg() {  # fetch_pkg PACKAGE:arm64 -> extracted dir path on stdout
  local pkg=$1 dir="$CACHE/x-${1%%:*}"
  if [ ! -f "$dir/.done" ]; then
    ( cd "$CACHE" && rm -f "${pkg%%:*}"_*.deb && apt-get download -q "$pkg" >/dev/null 2>&1 ) || {
      [ "$(id -u)" = 0 ] && apt-get update -q >/dev/null 2>&1
      ( cd "$CACHE" && apt-get download -q "$pkg" >/dev/null 2>&1 ) || return 1; }
    rm -rf "$dir" && mkdir -p "$dir" && dpkg-deb -x "$CACHE/${pkg%%:*}"_*.deb "$dir" && touch "$dir/.done"
  fi
  echo "$dir"
}
KPKG=$(apt-cache depends linux-image-rt-arm64:arm64 2>/dev/null | sed -n 's/.*Depends: \(linux-image-[0-9].*-rt-arm64\).*/\1/p' | head -1)
[ -n "$KPKG" ] || KPKG=$(ls -d "$CACHE"/x-linux-image-*-rt-arm64 2>/dev/null | head -1 | sed 's|.*/x-||')
[ -n "$KPKG" ] || die "cannot resolve the versioned package of linux-image-rt-arm64 (apt-get update?)"
KDIR=$(fetch_pkg "$KPKG:arm64") || die "cannot download $KPKG:arm64"
BBDIR=$(fetch_pkg busybox-static:arm64) || die "cannot download busybox-static:arm64"
CUDIR=$(fetch_pkg can-utils:arm64) || die "cannot download can-utils:arm64"
# socat receives the service's sd_notify datagrams in the guest (as systemd's NOTIFY_SOCKET would).
SOCATDIR=$(fetch_pkg socat:arm64) || die "cannot download socat:arm64"
WRAPDIR=$(fetch_pkg libwrap0:arm64) || die "cannot download libwrap0:arm64"
KVER=$(ls "$KDIR/lib/modules" | head -1)
KIMG=$KDIR/boot/vmlinuz-$KVER
[ -f "$KIMG" ] || die "no kernel image in $KPKG"
grep -q '^CONFIG_PREEMPT_RT=y' "$KDIR/boot/config-$KVER" && pass "kernel $KVER is PREEMPT_RT (from $KPKG, extracted, not installed)" \
  || fail "kernel $KVER is not PREEMPT_RT"

# ---- the amb-firmware package: this build's, and an upgrade (the next Debian revision) -----------
PKG=$WORK/pkg
cmake --build "$ARM_BUILD" --target amb-firmware amb_package_docs >/dev/null || die "cannot build amb-firmware and its package documents in $ARM_BUILD"
for rev in 1 2; do
  ( cd "$ARM_BUILD" && cpack -G DEB -D CPACK_DEBIAN_PACKAGE_RELEASE=$rev -D CPACK_OUTPUT_FILE_PREFIX="$PKG" \
      -D "CPACK_COMPONENTS_ALL=firmware" -B "$WORK/cpack-$rev" ) > "$WORK/cpack-$rev.log" 2>&1 \
    || die "cpack (revision $rev) failed: $(tail -5 "$WORK/cpack-$rev.log")"
done
DEB1=$(ls "$PKG"/amb-firmware_*-1_arm64.deb 2>/dev/null | head -1)
DEB2=$(ls "$PKG"/amb-firmware_*-2_arm64.deb 2>/dev/null | head -1)
[ -f "$DEB1" ] && [ -f "$DEB2" ] || die "no amb-firmware arm64 packages in $PKG: $(ls "$PKG")"
echo "packages: $(basename "$DEB1") ($(du -k "$DEB1" | cut -f1) KiB), upgrade $(basename "$DEB2")"
install_pkg() {  # install_pkg DEB: unpack into the image, as dpkg's unpack does, with the admin's config
  dpkg-deb -x "$1" "$R" || return 1
  mkdir -p "$R/var/lib/dpkg/info"
  # md5sums without the conffiles (dpkg checks those separately; the admin may edit them).
  dpkg-deb --ctrl-tarfile "$1" | tar -xO ./md5sums | grep -v ' etc/' > "$R/var/lib/dpkg/info/amb-firmware.md5sums" || return 1
  dpkg-deb -f "$1" Version > "$R/var/lib/dpkg/info/amb-firmware.version"
  # The administrator's edit of the conffile (dpkg keeps it across upgrades): this test's board.
  sed -i "s|^AMB_BOARD=.*|AMB_BOARD=/etc/amb/$BOARD.toml|" "$R/etc/amb/amb-firmware.conf"
}

# ---- initramfs ----------------------------------------------------------------------------------
R=$WORK/root
mkdir -p "$R"/{bin,sbin,usr/bin,proc,sys,dev,tmp,etc/amb,var/lib/amb,lib/modules,lib/aarch64-linux-gnu}
cp "$BBDIR/bin/busybox" "$R/bin/"
for a in $("$BBDIR/bin/busybox" --list 2>/dev/null || qemu-aarch64 "$BBDIR/bin/busybox" --list); do
  [ -e "$R/bin/$a" ] || ln -s busybox "$R/bin/$a"
done
cp "$PLANT" "$CUDIR/usr/bin/candump" "$CUDIR/usr/bin/cansend" "$SOCATDIR/usr/bin/socat" "$R/usr/bin/"
cp "$ROOT/boards/arm-virt-hil.toml" "$HERE/arm-virt-tracker.toml" "$R/etc/amb/"
# The board of this run: the tracker board (tachless speed source, a plant TCG can step in
# real time; see its header). AMB_TARGET_BOARD=arm-virt-hil runs the older board.
BOARD=${AMB_TARGET_BOARD:-arm-virt-tracker}
install_pkg "$DEB1" || die "cannot unpack $DEB1 into the image"
[ -x "$R/usr/bin/amb-firmware" ] && [ -f "$R/lib/systemd/system/amb-firmware.service" ] && [ -f "$R/etc/amb/amb-firmware.conf" ] \
  || die "the package lacks the binary, the unit or the config"
BOARD_TOML=$HERE/arm-virt-tracker.toml; [ "$BOARD" = arm-virt-hil ] && BOARD_TOML=$ROOT/boards/arm-virt-hil.toml
# Commands need the arm sequence (docs/register-map.md, "Write access"): [key hi, key lo,
# operation] to 0x0F00, then the command; the key is the board file's [comms.modbus] arm_key.
ARM_KEY=$(( $(sed -n 's/^arm_key *= *\([0-9xXa-fA-F]*\).*/\1/p' "$BOARD_TOML" | head -1) ))
cp "$HERE/guest-init.sh" "$R/init" && chmod +x "$R/init"
# Shared libraries: the NEEDED closure, from the multiarch arm64 install.
libdirs="/usr/lib/aarch64-linux-gnu /lib/aarch64-linux-gnu $WRAPDIR/lib/aarch64-linux-gnu $WRAPDIR/usr/lib/aarch64-linux-gnu"
todo="$R/usr/bin/amb-firmware $R/usr/bin/amb-plant $R/usr/bin/candump $R/usr/bin/cansend $R/usr/bin/socat"
seen=" "
while [ -n "$todo" ]; do
  next=""
  for bin in $todo; do
    for lib in $(readelf -d "$bin" 2>/dev/null | sed -n 's/.*Shared library: \[\(.*\)\].*/\1/p'); do
      case "$seen" in *" $lib "*) continue;; esac
      seen="$seen$lib "
      src=""
      for d in $libdirs; do [ -e "$d/$lib" ] && { src="$d/$lib"; break; }; done
      [ -n "$src" ] || die "arm64 library $lib not found (install the :arm64 -dev packages)"
      cp -L "$src" "$R/lib/aarch64-linux-gnu/$lib"
      next="$next $R/lib/aarch64-linux-gnu/$lib"
    done
  done
  todo=$next
done
# The loader must come from the same glibc as libc.so.6 (the multiarch libc6:arm64): the
# cross sysroot's copy (libc6-arm64-cross) may be another build, and a mismatched pair hangs
# in the first pthread_create.
LD=/lib/ld-linux-aarch64.so.1
for d in /lib /lib/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu; do
  [ -e "$d/ld-linux-aarch64.so.1" ] && { cp -L "$d/ld-linux-aarch64.so.1" "$R/lib/"; break; }
done
[ -e "$R$LD" ] || die "no arm64 dynamic loader ld-linux-aarch64.so.1"
KM=$KDIR/lib/modules/$KVER/kernel
for m in lib/crc16 crypto/crc32c_generic fs/mbcache fs/jbd2/jbd2 fs/ext4/ext4 drivers/virtio/virtio_mmio \
         drivers/block/virtio_blk net/core/failover drivers/net/net_failover drivers/net/virtio_net \
         net/can/can net/can/can-raw drivers/net/can/dev/can-dev drivers/net/can/vcan; do
  if [ -f "$KM/$m.ko" ]; then cp "$KM/$m.ko" "$R/lib/modules/"; fi  # absent: built in
done
make_initrd() { ( cd "$R" && find . | cpio -o -H newc 2>/dev/null | gzip -1 ) > "$WORK/initrd.gz"; }
make_initrd
echo "initramfs: $(du -h "$WORK/initrd.gz" | cut -f1), $(ls "$R/lib/aarch64-linux-gnu" | wc -l) shared libraries"

# ---- the board's disk and network ---------------------------------------------------------------
DISK=$WORK/data.img
mkfs.ext4 -q -F -L ambdata "$DISK" 64M || die "mkfs.ext4 failed"
PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
LOG=""

boot() {  # boot MODE [ANALYSIS]: start qemu with the serial console on a fifo (commands) and a log
  LOG=$WORK/console-$1.log
  local analysis=${2:-on}
  rm -f "$WORK/cmd"
  mkfifo "$WORK/cmd"
  timeout 900 qemu-system-aarch64 -M virt -cpu cortex-a57 -smp 2 -m 1024 -accel tcg \
    -kernel "$KIMG" -initrd "$WORK/initrd.gz" \
    -append "console=ttyAMA0 panic=-1 quiet amb.mode=$1 amb.board=$BOARD amb.analysis=$analysis" \
    -drive file="$DISK",format=raw,if=none,id=d0 -device virtio-blk-device,drive=d0 \
    -netdev user,id=n0,hostfwd=tcp:127.0.0.1:$PORT-:502 -device virtio-net-device,netdev=n0 \
    -display none -monitor none -serial stdio -no-reboot < "$WORK/cmd" > "$LOG" 2>&1 &
  QEMU_PID=$!
  exec 3> "$WORK/cmd"
}
wait_for() {  # wait_for PATTERN SECONDS
  local i=0
  while ! grep -q "$1" "$LOG" 2>/dev/null; do
    sleep 1; i=$((i + 1))
    if ! kill -0 "$QEMU_PID" 2>/dev/null; then
      grep -q "$1" "$LOG" 2>/dev/null && return 0
      echo "--- console:"; tail -n 40 "$LOG"; return 1
    fi
    [ $i -ge "$2" ] && { echo "--- console (timeout waiting for '$1'):"; tail -n 40 "$LOG"; return 1; }
  done
  return 0
}
send() { echo "$1" >&3; }
shutdown_vm() {
  send stop
  wait_for GUEST_STOPPED 120 || fail "guest did not stop cleanly"
  local i=0
  while kill -0 "$QEMU_PID" 2>/dev/null && [ $i -lt 30 ]; do sleep 1; i=$((i + 1)); done
  kill "$QEMU_PID" 2>/dev/null
  exec 3>&-
  QEMU_PID=""
}
MB="mbpoll -m tcp -p $PORT -a 1 -0 -1 -t 4:hex"
reg() {  # reg ADDRESS: one holding register (0-based) as a decimal, via mbpoll
  # mbpoll prints "[addr]: <unsigned>" or "[addr]: <unsigned> (<signed>)": keep the unsigned value.
  mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r "$1" -c 1 127.0.0.1 2>/dev/null | sed -n 's/^\[[0-9]*\]:[[:space:]]*\([0-9]*\).*/\1/p' | head -1
}
reg32() { local hi lo; hi=$(reg "$1"); lo=$(reg $(( $1 + 1 ))); echo $(( (${hi:-0} & 0xFFFF) * 65536 + (${lo:-0} & 0xFFFF) )); }
mb_arm() {  # mb_arm OPERATION: arm one command (1..6 command values, 16 event delete, 17 wear commit)
  mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r $((0x0F00)) 127.0.0.1 $(( (ARM_KEY >> 16) & 0xFFFF )) $(( ARM_KEY & 0xFFFF )) "$1" >/dev/null 2>&1
}
mb_cmd() { mb_arm "$1"; mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r 4096 127.0.0.1 "$1" >/dev/null 2>&1; }  # armed command

# ---- first boot ---------------------------------------------------------------------------------
T_BOOT=$(date +%s)
boot first
wait_for GUEST_READY 300 || die "board did not come up"
grep -q "GUEST: vcan0 up" "$LOG" && pass "vcan0 field bus up in the guest" || fail "vcan0 not up"
grep -q "gpiochip0 present" "$LOG" && pass "PL061 /dev/gpiochip0 present" || fail "no /dev/gpiochip0"
grep -q "GUEST-FW: amb-firmware: ready" "$LOG" && pass "amb-firmware (aarch64) running on the linux backend: $(grep -o 'ready: .*' "$LOG" | head -1)" \
  || die "amb-firmware did not start: $(grep GUEST-FW "$LOG" | tail -3)"
echo "boot to ready: $(( $(date +%s) - T_BOOT )) s"
rt_checks() {  # rt_checks LABEL: the installed service's package, unit settings and real-time state
  grep -q "GUEST-PKG: md5sums OK" "$LOG" && pass "$1: package $(grep -o 'GUEST-PKG: amb-firmware .*' "$LOG" | head -1 | cut -d' ' -f3) installed, its files match its md5sums ($(grep -o 'md5sums OK.*' "$LOG" | head -1))" \
    || fail "$1: installed files do not match the package's md5sums: $(grep GUEST-PKG "$LOG" | tail -3)"
  grep 'GUEST-UNIT\|GUEST-RT' "$LOG" | sed 's/^/  /'
  # The loop thread: SCHED_FIFO (policy 1) at priority 80, pinned to one CPU of the unit's set.
  local loop_line
  loop_line=$(grep 'GUEST-RT: tid .* policy 1 rtprio 80 ' "$LOG" | head -1)
  if [ -n "$loop_line" ] && echo "$loop_line" | grep -q 'cpus [0-9]*[[:space:]]*$'; then
    pass "$1: the service's loop thread runs SCHED_FIFO priority 80 on one CPU (/proc/<pid>/task/<tid>/stat: $(echo "$loop_line" | sed 's/.*GUEST-RT: //'))"
  else fail "$1: no SCHED_FIFO priority-80 loop thread pinned to one CPU in /proc: $(grep 'GUEST-RT: tid' "$LOG" | tr '\n' ' ')"; fi
  local vmlck
  vmlck=$(sed -n 's/.*GUEST-RT: pid .* VmLck \([0-9]*\) kB.*/\1/p' "$LOG" | head -1)
  [ "${vmlck:-0}" -gt 1024 ] && pass "$1: the service's memory is locked (/proc/<pid>/status VmLck ${vmlck} kB)" \
    || fail "$1: memory not locked (VmLck ${vmlck:-?} kB)"
  grep -q 'GUEST-RT: limit Max realtime priority *90 *90' "$LOG" && grep -q 'GUEST-RT: limit Max locked memory *unlimited *unlimited' "$LOG" \
    && pass "$1: the unit's LimitRTPRIO=90 and LimitMEMLOCK=infinity are the process's limits (/proc/<pid>/limits)" \
    || fail "$1: the unit's limits are not the process's: $(grep 'GUEST-RT: limit' "$LOG" | tr '\n' ' ')"
}
rt_checks "first boot"

i=0; until $MB -r 0 -c 1 127.0.0.1 >/dev/null 2>&1 || [ $i -ge 60 ]; do sleep 1; i=$((i + 1)); done
IDENT=$($MB -r 0 -c 24 127.0.0.1 2>&1)
if echo "$IDENT" | grep -q '^\[0\]:[[:space:]]*0x414D'; then
  pass "mbpoll (Debian) reads the identity block over the forwarded Modbus TCP port"
  echo "$IDENT" | grep '^\[' | head -8
else fail "mbpoll identity read: $IDENT"; fi
STATE=$(mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -r 256 -c 10 127.0.0.1 2>&1)
echo "$STATE" | grep -q '^\[256\]' && pass "mbpoll reads the state block (state $(reg 256), step count low word $(reg 263))" \
  || fail "mbpoll state read: $STATE"
OUT=$(mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -r 28672 -c 2 127.0.0.1 2>&1)
if echo "$OUT" | grep -qi 'illegal data address'; then
  pass "unknown address answered with Modbus exception 2 (illegal data address): $(echo "$OUT" | grep -i 'illegal' | head -1)"
else fail "unknown address not refused: $OUT"; fi
mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -r 256 127.0.0.1 7 >/dev/null 2>&1
EXC=$(reg32 $((0x522)))
[ "${EXC:-0}" -ge 2 ] && pass "bad Modbus requests counted by the board ($EXC exceptions)" || fail "Modbus exceptions not counted ($EXC)"

# Field bus: frames injected with cansend (can-utils) are decoded or refused and counted.
MAL0=$(reg32 $((0x514))); AMPF0=$(reg32 $((0x518)))
send inject
wait_for INJECT_DONE 60 || fail "inject"
sleep 2
MAL1=$(reg32 $((0x514))); AMPF1=$(reg32 $((0x518)))
[ $((MAL1 - MAL0)) -ge 2 ] && pass "malformed field-bus frames from cansend refused and counted ($((MAL1 - MAL0)))" \
  || fail "malformed frames not counted ($MAL0 -> $MAL1)"
[ $((AMPF1 - AMPF0)) -ge 1 ] && pass "valid amplifier-status frame from cansend decoded (amplifier fault seen)" \
  || fail "cansend amplifier-status frame not decoded ($AMPF0 -> $AMPF1)"
SAMPLES=$(reg32 $((0x510)))
[ "${SAMPLES:-0}" -gt 10 ] && pass "board receives samples from amb-plant over vcan0 ($SAMPLES)" || fail "no samples from amb-plant ($SAMPLES)"
echo "loop: periods $(reg32 $((0x402))) (low), overruns $(reg32 $((0x406))) (low), max latency $(reg32 $((0x408))) ns, p99 $(reg32 $((0x40C))) ns"

# Levitate, then lose the plant's nodes: the board must go to the safe state (comm_timeout or
# an earlier fault) and capture a drop event.
# A transport failure (time-out, connection refused while the loaded emulator is slow to close
# earlier connections) says nothing either way: retried up to 3 times and reported; an accepted
# write fails at once.
LV_TRIES=0
while :; do
  LV_TRIES=$((LV_TRIES + 1))
  LV=$(mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r 4096 127.0.0.1 1 2>&1)
  if echo "$LV" | grep -qi 'illegal function\|written'; then break; fi
  echo "unarmed levitate, try $LV_TRIES: no Modbus answer: $(echo "$LV" | tail -2 | tr '\n' ' ')"
  [ $LV_TRIES -ge 3 ] && break
  sleep 2
done
if echo "$LV" | grep -qi 'illegal function'; then
  pass "levitate without the arm sequence refused (exception 1) at try $LV_TRIES, state $(reg 256)"
else fail "levitate without the arm sequence not refused (state $(reg 256)): $(echo "$LV" | tail -3 | tr '\n' ' ')"; fi
mb_cmd 1
sleep 3
S=$(reg 256); F=$(reg 258)
echo "after levitate: state $S fault $F (2 levitating, 4 fault)"
if [ "$S" = 2 ]; then
  mb_arm 17
  WB=$(mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r $((0x5000)) 127.0.0.1 2 2>&1)
  if echo "$WB" | grep -qi 'busy'; then
    pass "armed write-back commit refused while levitating (exception 6)"
  else fail "write-back commit not refused while levitating (state now $(reg 256)): $(echo "$WB" | tail -2 | tr '\n' ' ')"; fi
fi
# Tachless speed on the board: spin up (run command), wait for the tracker's lock, then read the
# tracked-speed register with mbpoll and compare it with the HIL plant's true speed.
T_SPIN=$(date +%s)
spin_and_settle() {  # levitated -> run -> at speed, then 3 s for the tracker's 1 s windows
  mb_cmd 2
  local i=0
  while [ $i -lt 40 ] && [ "$(reg 257)" != 5 ]; do sleep 1; i=$((i + 1)); done
  sleep 3
}
loop_figures() {  # loop_figures LABEL: cumulative loop statistics from the registers
  echo "loop $1: periods $(reg32 $((0x402))), overruns $(reg32 $((0x406))), p99 $(reg32 $((0x40C))) ns, max $(reg32 $((0x408))) ns, mean $(reg32 $((0x40A))) ns (state $(reg 256), phase $(reg 257))"
  delay_figures "$1"
}
# The loop's delay, sample instant (deadline) -> demand frame written (registers 0x0410..,
# docs/plant.md "Loop delay"): the distribution the board key loop_delay_periods is set from.
delay_figures() {  # delay_figures LABEL
  local v; v=($(regs_block $((0x0410)) 16))
  if [ "${#v[@]}" -lt 16 ]; then echo "loop delay $1: registers 0x0410.. not read (${v[*]:-nothing})"; return; fi
  local q=() i
  for i in 0 2 4 6 8 10 12 14; do q+=($(( v[i] * 65536 + v[i + 1] ))); done
  echo "loop delay $1 (sample instant -> demand written): p50 ${q[0]} ns, p99 ${q[1]} ns, p99.9 ${q[2]} ns, max ${q[3]} ns, mean ${q[4]} ns; worst read ${q[5]} ns, step ${q[6]} ns, write ${q[7]} ns"
}
regs_block() {  # regs_block ADDRESS COUNT: the registers' unsigned values, space separated
  mbpoll -m tcp -p "$PORT" -a 1 -0 -1 -t 4 -o 5 -r "$1" -c "$2" 127.0.0.1 2>/dev/null | sed -n 's/^\[[0-9]*\]:[[:space:]]*\([0-9]*\).*/\1/p' | tr '\n' ' '
}
# The board's budget as it measures itself (registers 0x0700..0x0710, docs/register-map.md):
# locked and resident memory from /proc, CPU share of the loop and analysis threads over the
# last 20 s (their CPU clocks, read once a second outside the loop), process start to READY;
# and the buffer table computed from the board file (0x0720..).
budget_figures() {  # budget_figures LABEL LIMIT_KB: print, and check memory against the limit
  local v; v=($(regs_block $((0x0700)) 17))
  if [ "${#v[@]}" -lt 17 ]; then fail "$1: budget registers 0x0700.. not read (${v[*]:-nothing})"; return; fi
  local lck=$(( v[0] * 65536 + v[1] )) rss=$(( v[2] * 65536 + v[3] )) hwm=$(( v[4] * 65536 + v[5] ))
  local lcpu=${v[6]} acpu=${v[7]} win=${v[8]} ready=$(( v[9] * 65536 + v[10] )) evb=$(( v[11] * 65536 + v[12] ))
  local cap=$(( v[13] * 65536 + v[14] )) maxev=${v[15]} kept=${v[16]}
  share() { [ "$1" = 65535 ] && echo "-" || python3 -c "print('%.2f %%' % ($1 / 100.0))"; }
  echo "budget $1: VmLck $lck kB, VmRSS $rss kB (peak $hwm kB); CPU over the last $win s: loop thread $(share "$lcpu"), analysis thread $(share "$acpu"); process start to READY $ready ms; event file $evb B (worst case), store $cap KiB, max_events $maxev: keeps $kept events"
  local t; t=($(regs_block $((0x0720)) 23))
  echo "budget $1: buffer table (0x0720, fw::buffer_budget order, bytes): count ${t[0]:-?}: $(for ((k = 0; k < ${t[0]:-0}; k++)); do printf '%d ' $(( t[1 + 2 * k] * 65536 + t[2 + 2 * k] )); done)"
  if [ "$lck" -gt 1024 ] && [ "$lck" -le "$2" ] && [ "$rss" -gt 0 ] && [ "$rss" -le "$2" ]; then
    pass "$1: the service's memory fits its budget: VmLck $lck kB and VmRSS $rss kB <= $2 kB, locked (CPU over $win s: loop $(share "$lcpu"), analysis $(share "$acpu"))"
  else fail "$1: memory over the budget or not locked: VmLck $lck kB, VmRSS $rss kB (limit $2 kB)"; fi
}
BUDGET_KB=32768
SWEEP_EVENTS=0  # sweep events stored by this run (the drop-event count below leaves them out)
grep 'GUEST-RT: memory\|GUEST: service start to READY' "$LOG" | sed 's/^/  /'
if [ "$S" = 2 ] && [ "$BOARD" = arm-virt-tracker ]; then
  spin_and_settle
  # The plant's true speed first, then the tracked-speed register (retried while the tracker is
  # stale or lost: on a loaded host the emulated CPUs stall); registers are read one mbpoll at a
  # time, so the comparison uses the plant's speed and one valid read close to it.
  send plantspeed
  wait_for PLANT_SPEED_DONE 30 || fail "plant speed query"
  PS=$(grep 'GUEST-PLANT: amb-plant: true speed' "$LOG" | tail -1 | sed 's/.*true speed \([0-9.]*\).*/\1/')
  TS=2147483648; i=0
  while [ $i -lt 20 ]; do
    TS=$(reg32 $((0x306)))
    [ "${TS:-2147483648}" != 2147483648 ] && [ "${TS:-0}" -gt 0 ] && break
    sleep 1; i=$((i + 1))
  done
  TC=$(reg $((0x308))); FL=$(reg $((0x305))); EST=$(reg32 $((0x300)))
  grep '^STATUSFRAME' "$LOG" | head -3
  echo "tracked speed register 0x0306: $TS mHz (confidence $TC %, flags $FL, estimate 0x0300 $EST mHz; $i retries); plant true speed ${PS:-?} Hz; state $(reg 256) phase $(reg 257)"
  if python3 -c "import sys; t=int(sys.argv[1]); p=float(sys.argv[2]); sys.exit(0 if t != 2147483648 and p > 1 and abs(t*1e-3 - p)/p < 0.01 else 1)" "${TS:-2147483648}" "${PS:-0}"; then
    pass "mbpoll reads the board's tracked speed $(python3 -c "print('%.3f' % (int('$TS')*1e-3))") Hz within 1 % of the HIL plant's $PS Hz ($(( $(date +%s) - T_SPIN )) s after the run command)"
  else fail "tracked speed register ($TS mHz, flags $FL) not within 1 % of the plant's ${PS:-?} Hz"; fi
  grep -q '^STATUSFRAME:.* vcan0 501#' "$LOG" && pass "candump sees the board-status frame 0x501 (speed, confidence, flags)" \
    || fail "no board-status frame 0x501 on vcan0"
  # A short loop-sensitivity sweep over Modbus (docs/sweep.md "Board side"; the board's [sweep]:
  # one axis, 1 s periods, 1 + 2 periods): the host-built amb-host arms and starts it with the
  # board's key, polls its progress registers and downloads the new `sweep` event.
  # The analysis models the board file the guest runs (--model; it is not an embedded board) and
  # rates the axis per ISO 14839-3 (2 recorded periods: the residual loop is not run, a note says why).
  SJ=$("$HOST" sweep --connect 127.0.0.1 --port "$PORT" --arm-key "$ARM_KEY" --model "$BOARD_TOML" --out "$WORK/sweep" --timeout 120 --json 2>"$WORK/sweep.err")
  if [ $? -eq 0 ]; then
    SWEEP_EVENTS=1
    echo "$SJ" | python3 -c 'import json,sys; j=json.load(sys.stdin); print("  sweep event %s: %d bytes, %d lines %.1f .. %.1f Hz, amplitude %.3g A, crest factor %.2f" % (j["event"], j["event_bytes"], j["lines"], j["f_first_hz"], j["f_last_hz"], j["amplitude_a"], j["crest_factor"])); [print("  sweep axis %d: u/e peak %.3f at %.1f Hz" % (a["axis"], a["u_over_e_peak"], a["u_over_e_peak_hz"])) for a in j["axes"]]; [print("  ISO 14839-3 zone %s: %s; board model %.3f, zone %s" % (z["axis"], z["statement"], z["model_peak"], z["model_zone"])) for z in j["analysis"]["zones"]]'
    pass "amb-host sweep: a loop-sensitivity sweep armed, started, run and downloaded over Modbus (CRC-32C checked)"
  else fail "amb-host sweep: $(tail -3 "$WORK/sweep.err" | tr '\n' ' ') $SJ"; fi
  loop_figures "with the analysis thread ON"
  LOOP_ON=$(loop_figures on)
  budget_figures "analysis thread on, at speed" $BUDGET_KB
elif [ "$BOARD" = arm-virt-tracker ]; then
  # Not a skip: the board is made (250 Hz loop) for the emulator to hold; if it still cannot,
  # that is a finding (see docs/target-test.md).
  fail "tracked-speed mbpoll check not reached: the board is not levitated (state $S, fault $F)"
  loop_figures "with the analysis thread ON (not levitated)"
fi
send killplant
wait_for PLANT_KILLED 60 || fail "could not stop amb-plant"
grep 'GUEST-PLANT' "$LOG" | tail -1
i=0; n=0
while [ $i -lt 90 ]; do
  n=$("$HOST" fetch --host 127.0.0.1 --port "$PORT" --list --json 2>/dev/null | python3 -c 'import json,sys; print(json.load(sys.stdin)["events_on_board"])' 2>/dev/null || echo 0)
  [ "${n:-0}" -ge $((1 + SWEEP_EVENTS)) ] && break  # the sweep's event is stored there too
  sleep 2; i=$((i + 2))
done
n=$(( ${n:-0} - SWEEP_EVENTS ))
S=$(reg 256); F=$(reg 258)
[ "$S" = 4 ] && pass "board in the safe state after the drop (fault reason $F: 3 sensor_invalid = samples from the lagging emulated plant too late, 5 comm_timeout = nodes silent)" || fail "not in the safe state (state $S)"
[ "${n:-0}" -ge 1 ] && pass "drop event captured and stored on the board's disk ($n event(s))" || fail "no drop event on the board"
T_FETCH=$(date +%s)
FJ=$("$HOST" fetch --host 127.0.0.1 --port "$PORT" --out "$WORK/events" --json 2>&1)
if [ $? -eq 0 ] && [ "${n:-0}" -ge 1 ]; then
  echo "$FJ" | python3 -c 'import json,sys; j=json.load(sys.stdin); [print("  %s %d bytes crc32c %08x %s" % (e["name"], e["bytes"], e["crc32c"], e["status"])) for e in j["fetched"]]; print("  fetch throughput (emulated board, TCG): %.1f KiB/s, %d bytes in %.2f s" % (j["throughput_kib_s"], j["bytes"], j["wall_s"]))'
  pass "amb-host fetch downloaded the drop event(s), CRC-32C checked end to end"
else fail "amb-host fetch: $FJ"; fi

# Write a wear record back (encoded by an independent Python encoder of AMBW v1).
SEQ=$(( $(reg32 $((0x4001))) + 1 ))
python3 "$HERE/make_wear_record.py" "$WORK/wear.ambw" "$BOARD" "$SEQ" "${n:-1}" >/dev/null
WJ=$("$HOST" writeback "$WORK/wear.ambw" --board "$BOARD_TOML" --host 127.0.0.1 --port "$PORT" --json 2>&1)
if echo "$WJ" | grep -q '"verified": true'; then
  pass "amb-host writeback: record sequence $SEQ accepted, validated and persisted by the board"
else fail "amb-host writeback: $WJ"; fi
WCRC=$(echo "$WJ" | python3 -c 'import json,sys; print(json.load(sys.stdin)["crc32c"])' 2>/dev/null)
BAD=$WORK/bad.ambw; cp "$WORK/wear.ambw" "$BAD"; printf '\x02' | dd of="$BAD" bs=1 seek=4 conv=notrunc 2>/dev/null
"$HOST" writeback "$BAD" --board "$BOARD_TOML" --host 127.0.0.1 --port "$PORT" >/dev/null 2>&1 && fail "a record with a bad version was accepted" \
  || pass "a record with a bad version is refused"

send candump
wait_for CANDUMP_DONE 60 || fail "candump"
grep '^CANDUMP' "$LOG" | head -12
grep -q 'CANDUMP:.* vcan0 182#' "$LOG" && grep -q 'CANDUMP:.* vcan0 203#' "$LOG" && grep -q 'CANDUMP:.* vcan0 701#' "$LOG" \
  && pass "candump (can-utils) sees position (0x182), demand (0x203) and heartbeat (0x701) frames" \
  || fail "candump did not see the field-bus frames"
shutdown_vm
grep 'GUEST-FW: amb-firmware: stopped\|GUEST-FW: amb-firmware: CAN' "$LOG" | sed 's/^/  /'
# sd_notify: READY=1 once, then WATCHDOG=1 every WatchdogSec/2 while the loop runs.
NOTE=$(grep -o 'GUEST-NOTIFY: .*' "$LOG" | tail -1)
echo "  $NOTE"
NREADY=$(echo "$NOTE" | sed -n 's/.*READY=1 x\([0-9]*\).*/\1/p'); NPET=$(echo "$NOTE" | sed -n 's/.*WATCHDOG=1 x\([0-9]*\).*/\1/p')
NUP=$(echo "$NOTE" | sed -n 's/.* in \([0-9]*\) s.*/\1/p'); NWD=$(echo "$NOTE" | sed -n 's/.*WatchdogSec \([0-9]*\).*/\1/p')
if [ "${NREADY:-0}" = 1 ] && [ -n "$NUP" ] && [ -n "$NWD" ] && [ "${NPET:-0}" -ge $(( NUP / NWD )) ] && [ "${NPET:-0}" -le $(( 2 * NUP / NWD + 2 )) ]; then
  pass "sd_notify on the unit's NOTIFY_SOCKET: READY=1 once, WATCHDOG=1 $NPET times in $NUP s (WatchdogSec ${NWD} s: one per half interval while the loop ran)"
else fail "sd_notify: expected READY=1 once and about 2 WATCHDOG=1 per WatchdogSec: $NOTE"; fi
grep -q 'GUEST-FW: amb-firmware: stopped.*memory locked, SCHED_FIFO yes' "$LOG" \
  && pass "the firmware's own summary agrees: memory locked, SCHED_FIFO yes" || fail "firmware summary: $(grep 'GUEST-FW: amb-firmware: stopped' "$LOG")"
SUMS1=$WORK/sums-first-stop.txt
grep '^GUEST-SHA-STOP: ' "$LOG" | sed 's/^GUEST-SHA-STOP: //' > "$SUMS1"

# ---- upgrade: the next revision of the package unpacked over the installed one ------------------
# (the image is rebuilt with it, as an image-based board is upgraded; the data disk is the same)
install_pkg "$DEB2" || die "cannot unpack the upgrade $DEB2"
make_initrd

# ---- second boot: the wear record must still be there -------------------------------------------
# (and, on the tracker board, the same spin with the analysis thread off, for the latency figures)
boot second off
wait_for GUEST_READY 300 || die "board did not come up the second time"
i=0; until $MB -r 0 -c 1 127.0.0.1 >/dev/null 2>&1 || [ $i -ge 60 ]; do sleep 1; i=$((i + 1)); done
grep 'GUEST-FW: amb-firmware: storage' "$LOG" | sed 's/^/  /'
grep -q "GUEST-PKG: amb-firmware $(dpkg-deb -f "$DEB2" Version)[[:space:]]*\$" "$LOG" && pass "upgraded: the second boot runs amb-firmware $(dpkg-deb -f "$DEB2" Version) (was $(dpkg-deb -f "$DEB1" Version))" \
  || fail "the second boot does not run the upgrade: $(grep 'GUEST-PKG: amb-firmware' "$LOG")"
rt_checks "after the upgrade"
grep '^GUEST-SHA-BOOT: ' "$LOG" | sed 's/^GUEST-SHA-BOOT: //' > "$WORK/sums-upgrade-boot.txt"
if [ -s "$SUMS1" ] && grep -q '/wear/' "$SUMS1" && cmp -s "$SUMS1" "$WORK/sums-upgrade-boot.txt"; then
  pass "upgrade: the data disk holds the same wear record and events, byte-identical (sha256 of $(wc -l < "$SUMS1") files, wear $(grep '/wear/' "$SUMS1" | head -1 | cut -c1-16)...)"
else fail "upgrade: wear record or events changed: $(diff "$SUMS1" "$WORK/sums-upgrade-boot.txt" | head -5 | tr '\n' ' ')"; fi
"$HOST" fetch --host 127.0.0.1 --port "$PORT" --out "$WORK/after" --wear "$WORK/after.ambw" --json > "$WORK/after.json" 2>&1
if [ "$(reg32 $((0x4001)))" = "$SEQ" ] && cmp -s "$WORK/wear.ambw" "$WORK/after.ambw"; then
  pass "after a restart the board serves the same wear record (sequence $SEQ, byte-identical, crc32c $WCRC)"
else fail "wear record lost or changed across the restart: $(cat "$WORK/after.json")"; fi
if [ "$BOARD" = arm-virt-tracker ] && [ -n "${LOOP_ON:-}" ]; then
  mb_cmd 1
  sleep 3
  if [ "$(reg 256)" = 2 ]; then
    spin_and_settle
    sleep 4   # the on-run spent about this long reading the tracker and the plant
    echo "$LOOP_ON"
    loop_figures "with the analysis thread OFF"
    [ "$(reg $((0x305)))" -lt 64 ] && pass "analysis thread off (--no-analysis): speed flags say no tracker running" \
      || fail "analysis thread still reported running with --no-analysis"
    budget_figures "analysis thread off, at speed" $BUDGET_KB
    # Retention: the board file's store holds 3 events of this window (storage_capacity_bytes,
    # drop_oldest). Four manual captures (armed, 0x1000 <- 6) push it past its limit: the
    # oldest events must go, the newest stay, the wear record never changes (checked below).
    LIST0=$("$HOST" fetch --host 127.0.0.1 --port "$PORT" --list --json 2>/dev/null | python3 -c 'import json,sys; print(" ".join(e["name"] for e in json.load(sys.stdin)["list"]))' 2>/dev/null)
    DROP0=$(reg32 $((0x0544)))
    for k in 1 2 3 4; do mb_cmd 6; sleep 5; done
    sleep 3
    LIST1=$("$HOST" fetch --host 127.0.0.1 --port "$PORT" --list --json 2>/dev/null | python3 -c 'import json,sys; print(" ".join(e["name"] for e in json.load(sys.stdin)["list"]))' 2>/dev/null)
    DROP1=$(reg32 $((0x0544))); WRITTEN=$(reg32 $((0x0540)))
    echo "event store before the captures: ${LIST0:-none}"
    echo "event store after 4 manual captures: ${LIST1:-none} (events written $WRITTEN, dropped oldest $DROP0 -> $DROP1)"
    if python3 - "$LIST0" "$LIST1" "$DROP0" "$DROP1" <<'PY'
import sys
before = sorted(sys.argv[1].split()); after = sorted(sys.argv[2].split())
drop = int(sys.argv[4]) - int(sys.argv[3])
num = lambda n: int(n.split("_")[1].split(".")[0])
gone = [n for n in before if n not in after]
new = [n for n in after if n not in before]
# at most 3 kept (the board file's limit), the store went past it (something dropped),
# everything that went is older than everything kept, and all four captures are among the kept or dropped ones
ok = (len(after) == 3 and drop >= 1 and len(new) >= 1 and
      (not gone or max(map(num, gone)) < min(map(num, after))) and
      after == sorted(after, key=num) and max(map(num, after)) >= max(map(num, before or ["event_0.ambe"])) + 1)
sys.exit(0 if ok else 1)
PY
    then pass "event store past its limit (storage_capacity_bytes: 3 events): the oldest went first ($(( DROP1 - DROP0 )) dropped), the newest 3 kept: $LIST1"
    else fail "event store retention: before '$LIST0', after '$LIST1', dropped $DROP0 -> $DROP1"; fi
  else echo "second boot: not levitated (state $(reg 256)), no OFF figures"; fi
fi
shutdown_vm
# After the upgraded firmware has run: the wear record exactly as before, every earlier event
# unchanged (a new event of this boot may be added).
grep '^GUEST-SHA-STOP: ' "$LOG" | sed 's/^GUEST-SHA-STOP: //' > "$WORK/sums-second-stop.txt"
# An earlier event may be gone only by the store's retention (the fill above): then it is not on
# the disk at all; one that is there must be byte-identical.
CHANGED=""
while read -r sum path; do
  [ -z "$path" ] && continue
  if grep -q " $path\$" "$WORK/sums-second-stop.txt"; then grep -qxF "$sum $path" "$WORK/sums-second-stop.txt" || CHANGED="$CHANGED $path"; fi
done < <(grep '/events/' "$SUMS1")
if grep '/wear/' "$SUMS1" | cmp -s - <(grep '/wear/' "$WORK/sums-second-stop.txt") && [ -z "$CHANGED" ]; then
  pass "after the upgraded service ran: wear record byte-identical, the $(grep -c '/events/' "$SUMS1") earlier event(s) unchanged or removed by retention ($(grep -c '/events/' "$WORK/sums-second-stop.txt") now)"
else fail "the upgraded service changed the wear record or an event: $(diff "$SUMS1" "$WORK/sums-second-stop.txt" | head -5 | tr '\n' ' ')"; fi
echo "target test runtime: $(( $(date +%s) - T_START )) s"
