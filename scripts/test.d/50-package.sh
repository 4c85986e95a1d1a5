#!/usr/bin/env bash
# The Debian package: cpack builds the .deb from $BUILD_DIR, it holds everything in its FHS
# place with the config as a conffile, its maintainer scripts create the wheeltec user and
# leave the service disabled, and lintian reports no errors.
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
expect_file usr/lib/systemd/system/wheeltecd.service -rw-r--r--
expect_file usr/lib/systemd/network/80-wheeltec-can.network -rw-r--r--
expect_file etc/wheeltecd/wheeltecd.json -rw-r--r--
expect_file usr/share/man/man8/wheeltecd.8.gz -rw-r--r--
expect_file usr/share/man/man1/wheeltecctl.1.gz -rw-r--r--
expect_file usr/share/man/man1/wheeltec-emu.1.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/copyright -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/changelog.gz -rw-r--r--
expect_file usr/share/doc/wheeltec-gateway/deploy.md -rw-r--r--
if grep -q 'etc/systemd/system' <<<"$contents"; then fail "the package ships an enablement symlink"; fi

work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT
dpkg-deb -e "$deb" "$work/control"
grep -qxF /etc/wheeltecd/wheeltecd.json "$work/control/conffiles" || fail "the config is not a conffile"
# The shipped conffile is the defaults file but for api.control_groups = ["wheeltec"].
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./etc/wheeltecd/wheeltecd.json >"$work/shipped.json"
[[ $(jq -S 'del(.api.control_groups)' "$work/shipped.json") == $(jq -S 'del(.api.control_groups)' "$REPO_ROOT/config/wheeltecd.json") ]] ||
  fail "the shipped wheeltecd.json differs from config/wheeltecd.json in more than api.control_groups"
[[ $(jq -c .api.control_groups "$work/shipped.json") == '["wheeltec"]' ]] ||
  fail "the shipped wheeltecd.json does not let the group wheeltec drive"
grep -q '^Depends:.*adduser' "$work/control/control" || fail "Depends lacks adduser"
grep -q '^Depends:.*libjs-dygraphs' "$work/control/control" || fail "Depends lacks libjs-dygraphs (wheeltec-web's plots)"
grep -q 'adduser --system' "$work/control/postinst" || fail "postinst does not create the system user"
if grep -v '^[[:space:]]*#' "$work/control/postinst" | grep -Eq 'systemctl (--[a-z-]+ )*enable|deb-systemd-helper enable'; then
  fail "postinst enables the service"
fi
for script in postinst prerm postrm; do sh -n "$work/control/$script" || fail "$script: syntax error"; done
grep -q 'deb-systemd-invoke restart' "$work/control/postinst" || fail "postinst does not restart the service on upgrade"
grep -q 'purge' "$work/control/postrm" || fail "postrm does not handle purge"
for unit in wheeltecd.service wheeltec-mqtt.service wheeltec-web.service; do
  grep -q "$unit" "$work/control/postinst" || fail "postinst does not record or restart $unit"
  grep -q "$unit" "$work/control/prerm" || fail "prerm does not stop $unit"
  grep -q "$unit" "$work/control/postrm" || fail "postrm does not purge $unit"
done

# The man pages render without warnings.
dpkg-deb -x "$deb" "$work/root"
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
