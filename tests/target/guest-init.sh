#!/bin/sh
# /init of the emulated ARM board (tests/target/run-target-test.sh builds the initramfs).
# Brings up the field bus (vcan0), the network (QEMU user net), the data disk (the board's
# /var/lib/amb), starts amb-plant and the amb-firmware service (installed from its package:
# started as its systemd unit says, see start_service), then takes commands from the serial
# console, one per line, and answers with marker lines the host waits for.
export PATH=/bin:/sbin:/usr/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mkdir -p /tmp /var/lib/amb
mount -t tmpfs tmp /tmp
for m in crc16 crc32c_generic mbcache jbd2 ext4 virtio_mmio virtio_blk failover net_failover virtio_net \
         can can-raw can-dev vcan; do
  insmod /lib/modules/$m.ko 2>/dev/null || echo "GUEST: insmod $m failed"
done
echo "GUEST: kernel $(uname -r) $(grep -o 'PREEMPT_RT' /proc/version 2>/dev/null || uname -v)"
ip link set lo up
ip addr add 10.0.2.15/24 dev eth0
ip link set eth0 up
ip link add dev vcan0 type vcan && ip link set vcan0 up && echo "GUEST: vcan0 up"
i=0
while [ ! -b /dev/vda ] && [ $i -lt 50 ]; do sleep 0.1; i=$((i+1)); done
mount -t ext4 -o sync /dev/vda /var/lib/amb || echo "GUEST: FAILED to mount /var/lib/amb"
ls /dev/gpiochip* >/dev/null 2>&1 && echo "GUEST: $(ls /dev/gpiochip*) present"
MODE=$(sed -n 's/.*amb\.mode=\([a-z0-9]*\).*/\1/p' /proc/cmdline)
BOARD=$(sed -n 's/.*amb\.board=\([a-z0-9-]*\).*/\1/p' /proc/cmdline)
[ -n "$BOARD" ] || BOARD=arm-virt-hil
ANALYSIS=$(sed -n 's/.*amb\.analysis=\([a-z]*\).*/\1/p' /proc/cmdline)
echo "GUEST: mode $MODE, board $BOARD, analysis ${ANALYSIS:-on}"

# The package as installed: its files against its md5sums, and the data it finds on the disk
# (wear record, events) before the firmware of this boot touches it.
echo "GUEST-PKG: amb-firmware $(cat /var/lib/dpkg/info/amb-firmware.version)"
( cd / && md5sum -c /var/lib/dpkg/info/amb-firmware.md5sums >/tmp/md5.log 2>&1 ) \
  && echo "GUEST-PKG: md5sums OK ($(wc -l < /tmp/md5.log) files)" || { echo "GUEST-PKG: md5sums FAILED"; sed 's/^/GUEST-PKG: /' /tmp/md5.log; }
data_sums() {  # data_sums TAG: sha256 of every wear-record and event file on the data disk
  for f in $(find /var/lib/amb/wear /var/lib/amb/events -type f 2>/dev/null | sort); do
    echo "$1: $(sha256sum "$f" | cut -d' ' -f1) $f"
  done
}
data_sums GUEST-SHA-BOOT

# What systemd does with /lib/systemd/system/amb-firmware.service, done by this busybox init:
# the EnvironmentFile (the conffile /etc/amb/amb-firmware.conf), LimitRTPRIO and LimitMEMLOCK
# (ulimit -r / -l), CPUAffinity (taskset -c) and the ExecStart command line with its ${VAR}
# and $VAR expanded from the environment file. The unit's values are read from the unit file.
start_service() {
  UNIT=/lib/systemd/system/amb-firmware.service
  unitval() { sed -n "s/^$1=//p" $UNIT | tail -n 1; }
  set -a; . "$(unitval EnvironmentFile)"; set +a
  [ "$ANALYSIS" = off ] && AMB_OPTIONS="$AMB_OPTIONS --no-analysis"
  RTPRIO=$(unitval LimitRTPRIO); MEMLOCK=$(unitval LimitMEMLOCK); AFF=$(unitval CPUAffinity)
  [ "$MEMLOCK" = infinity ] && MEMLOCK=unlimited
  EXEC=$(unitval ExecStart)
  # Type=notify + WatchdogSec: systemd's NOTIFY_SOCKET and WATCHDOG_USEC; socat is the receiver.
  WDSEC=$(unitval WatchdogSec | tr -d 's')
  mkdir -p /run
  socat -u UNIX-RECV:/run/amb-notify,unlink-early OPEN:/tmp/notify.log,creat,append 2>/tmp/socat.err &
  NOTIFY=$!
  i=0; while [ ! -S /run/amb-notify ] && [ $i -lt 50 ]; do sleep 0.1; i=$((i+1)); done
  export NOTIFY_SOCKET=/run/amb-notify WATCHDOG_USEC=$((WDSEC * 1000000))
  FW_T0=$(cut -d. -f1 /proc/uptime)
  FW_T0_CS=$(cut -d' ' -f1 /proc/uptime | tr -d .)   # centiseconds since boot
  echo "GUEST-UNIT: LimitRTPRIO=$RTPRIO LimitMEMLOCK=$MEMLOCK CPUAffinity=$AFF ExecStart=$EXEC (AMB_BOARD=$AMB_BOARD AMB_DATA_DIR=$AMB_DATA_DIR AMB_OPTIONS=$AMB_OPTIONS)"
  ( ulimit -r "$RTPRIO" && ulimit -l "$MEMLOCK" || echo "GUEST-UNIT: ulimit failed"
    eval "exec taskset -c $AFF $EXEC" ) > /tmp/firmware.log 2>&1 &
  FW=$!
}
# The real-time state of the running service, from /proc: per thread the scheduling policy
# (stat field 41: 0 other, 1 FIFO) and priority (field 40) and the CPUs allowed; VmLck; limits.
rt_report() {
  echo "GUEST-RT: pid $FW comm $(cat /proc/$FW/comm) VmLck $(sed -n 's/^VmLck:[[:space:]]*//p' /proc/$FW/status)"
  echo "GUEST-RT: memory VmLck $(sed -n 's/^VmLck:[[:space:]]*//p' /proc/$FW/status) VmRSS $(sed -n 's/^VmRSS:[[:space:]]*//p' /proc/$FW/status) VmHWM $(sed -n 's/^VmHWM:[[:space:]]*//p' /proc/$FW/status) threads $(ls /proc/$FW/task | wc -l)"
  for t in /proc/$FW/task/*; do
    echo "GUEST-RT: tid ${t##*/} $(sed 's/^.*) //' $t/stat | awk '{print "policy", $39, "rtprio", $38}') cpus $(sed -n 's/^Cpus_allowed_list:[[:space:]]*//p' $t/status)"
  done
  grep 'realtime priority\|locked memory' /proc/$FW/limits | sed 's/^/GUEST-RT: limit /'
}

candump -L -n 3000 vcan0 > /tmp/candump.log 2>&1 &
CANDUMP=$!
amb-plant --board /etc/amb/$BOARD.toml > /tmp/plant.log 2>&1 &
PLANT=$!
start_service
i=0
while ! grep -q "READY=1" /tmp/firmware.log && [ $i -lt 1200 ] && kill -0 $FW 2>/dev/null; do sleep 0.1; i=$((i+1)); done
FW_T1_CS=$(cut -d' ' -f1 /proc/uptime | tr -d .)
echo "GUEST: firmware start took $((i / 10)) s"
echo "GUEST: service start to READY=1 in the log: $(( (FW_T1_CS - FW_T0_CS) * 10 )) ms (polled every 0.1 s)"
sed 's/^/GUEST-FW: /' /tmp/firmware.log
kill -0 $FW 2>/dev/null && rt_report
echo "GUEST_READY"

while read -r cmd; do
  case "$cmd" in
    inject)
      # A valid amplifier-status frame reporting a fault (flags 0x03: enabled + fault) and one
      # clearing it again (flags 0x01), a
      # position frame one byte short, a heartbeat with an undefined NMT state, and frames of
      # a node nobody listens to.
      cansend vcan0 383#0301E001B4010000
      cansend vcan0 383#0102E001B4010000
      cansend vcan0 182#01020304050607
      cansend vcan0 702#33
      cansend vcan0 185#0000000000000000
      echo "INJECT_DONE";;
    plantspeed)
      # The plant's true rotor speed (amb-plant prints it on SIGUSR1) and a few board-status
      # frames (0x501: the board's speed estimate, confidence, flags) seen with candump.
      kill -USR1 $PLANT
      sleep 0.5
      grep 'true speed' /tmp/plant.log | tail -1 | sed 's/^/GUEST-PLANT: /'
      timeout 3 candump -L -n 3 vcan0,501:7FF 2>&1 | sed 's/^/STATUSFRAME: /'
      echo "PLANT_SPEED_DONE";;
    killplant)
      kill $PLANT
      i=0; while kill -0 $PLANT 2>/dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i+1)); done
      kill -9 $PLANT 2>/dev/null
      sed 's/^/GUEST-PLANT: /' /tmp/plant.log
      echo "PLANT_KILLED";;
    candump)
      kill $CANDUMP 2>/dev/null
      echo "GUEST: candump captured $(wc -l < /tmp/candump.log) frames"
      grep -m 3 ' vcan0 182#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      grep -m 3 ' vcan0 283#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      grep -m 2 ' vcan0 203#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      grep -m 2 ' vcan0 303#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      grep -m 1 ' vcan0 701#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      grep -m 1 ' vcan0 383#' /tmp/candump.log | sed 's/^/CANDUMP: /'
      echo "CANDUMP_DONE";;
    stop)
      kill $FW
      i=0; while kill -0 $FW 2>/dev/null && [ $i -lt 300 ]; do sleep 0.1; i=$((i+1)); done
      sed 's/^/GUEST-FW: /' /tmp/firmware.log | tail -n 6
      sleep 0.3; kill $NOTIFY 2>/dev/null
      echo "GUEST-NOTIFY: READY=1 x$(grep -o 'READY=1' /tmp/notify.log | wc -l) WATCHDOG=1 x$(grep -o 'WATCHDOG=1' /tmp/notify.log | wc -l) STOPPING=1 x$(grep -o 'STOPPING=1' /tmp/notify.log | wc -l) in $(( $(cut -d. -f1 /proc/uptime) - FW_T0 )) s, WatchdogSec $WDSEC s $(cat /tmp/socat.err)"
      kill $PLANT 2>/dev/null
      ls -l /var/lib/amb/events /var/lib/amb/wear | sed 's/^/GUEST-DATA: /'
      data_sums GUEST-SHA-STOP
      umount /var/lib/amb; sync
      echo "GUEST_STOPPED"
      poweroff -f;;
    "") ;;
    *) echo "GUEST: unknown command '$cmd'";;
  esac
done
poweroff -f
