#!/usr/bin/env bash
# The Debian package: cpack builds the .deb from $BUILD_DIR, it holds everything in its FHS
# place with the config as a conffile, its maintainer scripts create the wheeltec user and
# leave the service disabled, the udev rule names only the vendor's serial cable (udevadm test
# on a made-up sysfs), and lintian reports no errors.
set -euo pipefail
: "${REPO_ROOT:?}" "${BUILD_DIR:?}"
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages dpkg-dev lintian groff-base jq

cmake --build "$BUILD_DIR" -j "${BUILD_JOBS:-2}"
rm -f "$BUILD_DIR"/wheeltec-gateway_*.deb
(cd "$BUILD_DIR" && cpack -G DEB)
deb=$(ls "$BUILD_DIR"/wheeltec-gateway_*.deb)
echo "package: $deb ($(stat -c %s "$deb") bytes)"

status=0
fail() { echo "FAIL: $*"; status=1; }

contents=$(dpkg-deb -c "$deb" | awk '{print $1, $6}')
expect_file() {  # PATH MODE
  grep -qxF -- "$2 ./$1" <<<"$contents" || fail "$1 missing or not $2"
}
expect_file usr/bin/wheeltecd -rwxr-xr-x
expect_file usr/bin/wheeltecctl -rwxr-xr-x
expect_file usr/bin/wheeltec-emu -rwxr-xr-x
expect_file usr/bin/wheeltec-mqtt -rwxr-xr-x
expect_file usr/lib/systemd/system/wheeltec-mqtt.service -rw-r--r--
expect_file usr/share/man/man1/wheeltec-mqtt.1.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/fleet.md -rw-r--r--
expect_file usr/bin/wheeltec-web -rwxr-xr-x
expect_file usr/lib/systemd/system/wheeltec-web.service -rw-r--r--
expect_file usr/share/man/man1/wheeltec-web.1.gz -rw-r--r--
expect_file usr/share/wheeltec-web/index.html -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/web.md -rw-r--r--
expect_file usr/bin/wheeltec-ros2 -rwxr-xr-x
expect_file usr/lib/systemd/system/wheeltec-ros2.service -rw-r--r--
expect_file usr/share/man/man1/wheeltec-ros2.1.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/ros2.md -rw-r--r--
expect_file usr/lib/systemd/system/wheeltecd.service -rw-r--r--
expect_file usr/lib/systemd/network/80-wheeltec-can.network -rw-r--r--
expect_file usr/lib/udev/rules.d/60-wheeltec-controller.rules -rw-r--r--
expect_file etc/wheeltecd/wheeltecd.json -rw-r--r--
expect_file usr/share/man/man8/wheeltecd.8.gz -rw-r--r--
expect_file usr/share/man/man1/wheeltecctl.1.gz -rw-r--r--
expect_file usr/share/man/man1/wheeltec-emu.1.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/copyright -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/changelog.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/deploy.md -rw-r--r--
for file in __init__.py aio.py client.py connection.py errors.py protocol.py records.py py.typed; do
  expect_file "usr/lib/python3/dist-packages/wheeltec/$file" -rw-r--r--
done
expect_file usr/share/doc/wheeltec-gateway/python.md -rw-r--r--
if grep -q 'etc/systemd/system' <<<"$contents"; then fail "the package ships an enablement symlink"; fi

work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT
dpkg-deb -e "$deb" "$work/control"
grep -qxF /etc/wheeltecd/wheeltecd.json "$work/control/conffiles" || fail "the config is not a conffile"
# The shipped conffile is the defaults file but for api.control_groups = ["wheeltec"] and the
# emergency stop's state file in the unit's StateDirectory.
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./etc/wheeltecd/wheeltecd.json >"$work/shipped.json"
[[ $(jq -S 'del(.api.control_groups, .safety.state_file)' "$work/shipped.json") == $(jq -S 'del(.api.control_groups, .safety.state_file)' "$REPO_ROOT/config/wheeltecd.json") ]] ||
  fail "the shipped wheeltecd.json differs from config/wheeltecd.json in more than api.control_groups and safety.state_file"
[[ $(jq -r .safety.state_file "$work/shipped.json") == /var/lib/wheeltecd/safety.json ]] ||
  fail "the shipped wheeltecd.json keeps the latch elsewhere than /var/lib/wheeltecd/safety.json"
[[ $(jq -c .api.control_groups "$work/shipped.json") == '["wheeltec"]' ]] ||
  fail "the shipped wheeltecd.json does not let the group wheeltec drive"
grep -q '^Depends:.*adduser' "$work/control/control" || fail "Depends lacks adduser"
grep -q '^Depends:.*libjs-dygraphs' "$work/control/control" || fail "Depends lacks libjs-dygraphs (wheeltec-web's plots)"
grep -q '^Depends:.*libddsc0debian' "$work/control/control" || fail "Depends lacks libddsc0debian (wheeltec-ros2's Cyclone DDS)"
grep -Eq '^Depends:.*python3(,|$)' "$work/control/control" || fail "Depends lacks python3 (the Python client)"
grep -q 'adduser --system' "$work/control/postinst" || fail "postinst does not create the system user"
if grep -v '^[[:space:]]*#' "$work/control/postinst" | grep -Eq 'systemctl (--[a-z-]+ )*enable|deb-systemd-helper enable'; then
  fail "postinst enables the service"
fi
for script in postinst prerm postrm; do sh -n "$work/control/$script" || fail "$script: syntax error"; done
grep -q 'deb-systemd-invoke restart' "$work/control/postinst" || fail "postinst does not restart the service on upgrade"
grep -q 'purge' "$work/control/postrm" || fail "postrm does not handle purge"
for unit in wheeltecd.service wheeltec-mqtt.service wheeltec-web.service wheeltec-ros2.service; do
  grep -q "$unit" "$work/control/postinst" || fail "postinst does not record or restart $unit"
  grep -q "$unit" "$work/control/prerm" || fail "prerm does not stop $unit"
  grep -q "$unit" "$work/control/postrm" || fail "postrm does not purge $unit"
done

# The udev rule is applied at install to a cable already plugged in, only where udev runs.
grep -q 'udevadm trigger --action=change' "$work/control/postinst" || fail "postinst does not apply the udev rule"
grep -q -- '-S /run/udev/control' "$work/control/postinst" || fail "postinst runs udevadm without checking that udev runs"

dpkg-deb -x "$deb" "$work/root"

# The Python client as installed: the system's python3 imports it from the package's files.
PYTHONPATH=$work/root/usr/lib/python3/dist-packages /usr/bin/python3 -c '
import sys, wheeltec
assert wheeltec.__file__.startswith(sys.argv[1]), wheeltec.__file__
assert wheeltec.aio.Client and wheeltec.Client and wheeltec.EmergencyStopLatched.CODE == -32007
' "$work/root/" || fail "python3 cannot import wheeltec from the package"

# The udev rule, as shipped, under Debian's udevadm: `udevadm test` on a made-up sysfs, in a
# mount namespace of its own (tmpfs over /sys, /run and /dev, so nothing on this machine
# changes). Only a CP2102 (10c4:ea60) or CH343 (1a86:55d4) with WHEELTEC's serial string 0002
# becomes /dev/wheeltec_controller, group wheeltec, mode 0660, ignored by ModemManager and
# without gpsd's hotplug; the vendor's lidar (0001), other CP2102s and a CH340 keep their
# names; the file parses without a complaint. Debian 12's udevadm (252) has no `verify`;
# where a newer one has, it runs too. No udev here: udevadm comes from Debian's udev
# package, unpacked into the scratch directory, not installed.
udev_rule=usr/lib/udev/rules.d/60-wheeltec-controller.rules
udevadm=$(command -v udevadm || true)
if [[ -z $udevadm ]]; then
  mkdir -p "$work/udev"
  (cd "$work/udev" && apt-get download udev >/dev/null 2>&1) ||
    (cd "$work/udev" && apt-get update >/dev/null 2>&1 && apt-get download udev >/dev/null 2>&1) || true
  if deb_udev=$(ls "$work"/udev/udev_*.deb 2>/dev/null) && dpkg-deb -x "$deb_udev" "$work/udev/root"; then
    udevadm=$work/udev/root/bin/udevadm
  fi
fi
if [[ -z $udevadm ]]; then
  fail "no udevadm to check $udev_rule with (apt-get download udev failed)"
else
  if "$udevadm" verify --help >/dev/null 2>&1; then
    "$udevadm" verify "$work/root/$udev_rule" || fail "udevadm verify: $udev_rule"
  fi
  cat >"$work/udev-test.sh" <<'SCRIPT'
# Runs inside `unshare`: RULE UDEVADM; prints "=== DEVICE" and udevadm test's output for each.
set -euo pipefail
rule=$1 udevadm=$2
mount -t tmpfs none /run
touch /run/null && mount --bind /dev/null /run/null
mount -t tmpfs none /dev
touch /dev/null && mount --bind /run/null /dev/null
mount -t tmpfs none /sys
mkdir -p /run/udev/rules.d /sys/class/tty /sys/bus/usb /sys/bus/usb-serial
cp "$rule" /run/udev/rules.d/
# Debian 12's gpsd: /usr/lib/udev/rules.d/60-gpsd.rules, its line for the CP2102.
echo 'SUBSYSTEM=="tty", ATTRS{idVendor}=="10c4", ATTRS{idProduct}=="ea60", SYMLINK+="gps%n", TAG+="systemd", ENV{SYSTEMD_WANTS}="gpsdctl@%k.service"' \
  >/run/udev/rules.d/60-gpsd.rules
if ! grep -q '^wheeltec:' /etc/group; then
  cp /etc/group /run/group && echo 'wheeltec:x:990:' >>/run/group && mount --bind /run/group /etc/group
fi
usb=/sys/devices/pci0000:00/0000:00:14.0/usb1
mkdir -p $usb && echo DEVTYPE=usb_device >$usb/uevent && ln -s /sys/bus/usb $usb/subsystem
add() {  # PORT VENDOR PRODUCT SERIAL TTY MAJOR MINOR
  local dev=$usb/$1 interface=$usb/$1/$1:1.0 tty
  mkdir -p "$interface"
  printf 'DEVTYPE=usb_device\nPRODUCT=%s/%s/100\n' "$2" "$3" >"$dev/uevent"
  echo "$2" >"$dev/idVendor" && echo "$3" >"$dev/idProduct" && echo "$4" >"$dev/serial"
  echo DEVTYPE=usb_interface >"$interface/uevent"
  ln -s /sys/bus/usb "$dev/subsystem" && ln -s /sys/bus/usb "$interface/subsystem"
  if [[ $5 == ttyUSB* ]]; then  # usb-serial: a port device between interface and tty
    mkdir -p "$interface/$5" && : >"$interface/$5/uevent" && ln -s /sys/bus/usb-serial "$interface/$5/subsystem"
    tty=$interface/$5/tty/$5
  else
    tty=$interface/tty/$5
  fi
  mkdir -p "$tty"
  printf 'MAJOR=%s\nMINOR=%s\nDEVNAME=%s\n' "$6" "$7" "$5" >"$tty/uevent" && echo "$6:$7" >"$tty/dev"
  ln -s /sys/class/tty "$tty/subsystem" && ln -s "$tty" "/sys/class/tty/$5"
}
add 1-1 10c4 ea60 0002 ttyUSB0 188 0        # the controller's CP2102 cable
add 1-2 10c4 ea60 0001 ttyUSB1 188 1        # WHEELTEC's lidar cable
add 1-3 10c4 ea60 0123456789 ttyUSB2 188 2  # any other CP2102
add 1-4 1a86 7523 0002 ttyUSB3 188 3        # a CH340
add 1-5 1a86 55d4 0002 ttyACM0 166 0        # the controller's CH343, kernel driver cdc_acm
add 1-6 1a86 55d4 0002 ttyCH343USB0 170 0   # the same with WCH's driver
add 1-7 1a86 55d4 0001 ttyACM1 166 1        # WHEELTEC's lidar on a CH343
for tty in ttyUSB0 ttyUSB1 ttyUSB2 ttyUSB3 ttyACM0 ttyCH343USB0 ttyACM1; do
  echo "=== $tty"
  SYSTEMD_DEVICE_VERIFY_SYSFS=0 "$udevadm" test --action=add "/sys/class/tty/$tty" 2>&1
done
SCRIPT
  unshare_as=(unshare --mount --propagation private)
  [[ $(id -u) -eq 0 ]] || unshare_as=(unshare --user --map-root-user --mount --propagation private)
  if ! udev_output=$("${unshare_as[@]}" bash "$work/udev-test.sh" "$work/root/$udev_rule" "$udevadm" 2>&1); then
    fail "udevadm test on a made-up sysfs did not run: $(tail -3 <<<"$udev_output")"
  fi
  gid=$(sed -n 's/^wheeltec:[^:]*:\([0-9]*\):.*/\1/p' /etc/group); gid=${gid:-990}
  device_output() { awk -v d="=== $1" '$0 == d {on = 1; next} /^=== / {on = 0} on' <<<"$udev_output"; }
  status_before_udev=$status
  if problems=$(grep -E '^/run/udev/rules.d/60-wheeltec-controller.rules' <<<"$udev_output" | sort -u); then
    fail "udevadm complains about $udev_rule: $problems"
  fi
  for tty in ttyUSB0 ttyACM0 ttyCH343USB0; do
    out=$(device_output "$tty")
    grep -q '^DEVLINKS=.*/dev/wheeltec_controller' <<<"$out" || fail "udev: $tty (vendor's cable) is not /dev/wheeltec_controller"
    grep -q "60-wheeltec-controller.rules:[0-9]* GROUP $gid\$" <<<"$out" || fail "udev: $tty does not get the group wheeltec ($gid)"
    grep -q '60-wheeltec-controller.rules:[0-9]* MODE 0660$' <<<"$out" || fail "udev: $tty does not get mode 0660"
    grep -qx 'ID_MM_DEVICE_IGNORE=1' <<<"$out" || fail "udev: ModemManager does not ignore $tty"
    if grep -q '^SYSTEMD_WANTS=.*gpsdctl' <<<"$out"; then fail "udev: gpsd's hotplug still wants $tty"; fi
  done
  for tty in ttyUSB1 ttyUSB2 ttyUSB3 ttyACM1; do
    out=$(device_output "$tty")
    [[ -n $out ]] || fail "udev: no udevadm test output for $tty"
    if grep -qE 'wheeltec_controller|ID_MM_DEVICE_IGNORE|60-wheeltec-controller.rules:[0-9]' <<<"$out"; then
      fail "udev: the rule takes $tty, which is not the vendor's controller cable"
    fi
  done
  grep -q '^SYSTEMD_WANTS=gpsdctl@ttyUSB2.service' <<<"$(device_output ttyUSB2)" ||
    fail "udev: the check's stand-in for gpsd's rule did not apply (the check itself is broken)"
  ((status != status_before_udev)) || echo "udev rule: the controller's cables only (udevadm test, udev $("$udevadm" --version))"
fi

# The man pages render without warnings.
for page in "$work"/root/usr/share/man/man*/*.gz; do
  warnings=$(zcat "$page" | groff -man -Tutf8 -ww -z 2>&1) || true
  [[ -z $warnings ]] || fail "$(basename "$page"): $warnings"
done

# lintian: no errors (warnings and info are printed but allowed).
lintian_output=$(lintian --allow-root "$deb" 2>&1) || true
[[ -n $lintian_output ]] && echo "$lintian_output"
if grep -q '^E: ' <<<"$lintian_output"; then fail "lintian reports errors"; fi

((status == 0)) && echo "package checks: OK"
exit "$status"
