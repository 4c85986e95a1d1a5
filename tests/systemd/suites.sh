#!/usr/bin/env bash
# Runs several scripts of the systemd suite in one User-Mode Linux session, one after
# another, each from the state a session of its own would give it: booting systemd costs
# more than most suites' checks (scripts/systemd-uml prints it), so the session boots once.
# Run as root inside scripts/systemd-uml --no-install:
#
#   suites.sh NAME:SECONDS...
#
# Each NAME.sh (this directory) runs with a time limit of SECONDS and its output labelled
# "[NAME] ". Before each, a reset gives it what a fresh session would: the services
# stopped, the package purged (its configuration, enablement and the bridges' /etc and
# /var/lib directories with it), the users and groups made since the session started
# removed (the package's wheeltec too, which a fresh machine does not have), the journal
# emptied, and then the package installed with dpkg -i, as systemd-uml does; lifecycle,
# which installs the package itself, gets it not installed. A suite's leftover processes
# (its process group) are killed when it ends. $WHEELTEC_SYSTEMD_ONLY (names, space- or
# comma-separated) runs only those. Exits 1 if any suite failed, naming each.
set -uo pipefail
: "${SYSTEMD_UML_DEB:?the package to install (run inside scripts/systemd-uml)}"

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
readonly HERE
readonly PACKAGE=wheeltec-gateway
readonly UNITS=(wheeltec-web.service wheeltec-mqtt.service wheeltec-ros2.service
                wheeltec-record.service wheeltecd.service)
say() { echo "systemd-suites: $*"; }
ms_since() { echo $((($(date +%s%N) - $1) / 1000000)); }

only=" ${WHEELTEC_SYSTEMD_ONLY//,/ } "
suites=()
for entry in "$@"; do
  [[ $entry =~ ^[a-z0-9-]+:[0-9]+$ ]] || { say "bad suite '$entry' (NAME:SECONDS)"; exit 2; }
  [[ -f $HERE/${entry%%:*}.sh ]] || { say "no suite ${entry%%:*} ($HERE/${entry%%:*}.sh)"; exit 2; }
  [[ $only == "  " || $only == *" ${entry%%:*} "* ]] && suites+=("$entry")
done
((${#suites[@]})) || { say "no suite to run"; exit 2; }

# What the session had before any suite: the users and groups to keep.
base_users=$(getent passwd | cut -d: -f1 | sort)
base_groups=$(getent group | cut -d: -f1 | sort)

# reset: the state of a freshly booted session, the package not installed.
reset() {
  systemctl stop "${UNITS[@]}" 2>/dev/null
  systemctl disable "${UNITS[@]}" 2>/dev/null
  systemctl reset-failed 2>/dev/null
  if dpkg-query -W -f='${db:Status-Status}' "$PACKAGE" 2>/dev/null | grep -qv '^not-installed$'; then
    DEBIAN_FRONTEND=noninteractive dpkg -P "$PACKAGE" >/dev/null || { say "dpkg -P $PACKAGE failed"; return 1; }
  fi
  local name
  for name in $(comm -13 <(echo "$base_users") <(getent passwd | cut -d: -f1 | sort)); do
    userdel -r -f "$name" >/dev/null 2>&1  # exit 12 for a home that is not there (/nonexistent)
    ! getent passwd "$name" >/dev/null || { say "cannot remove user $name"; return 1; }
  done
  for name in $(comm -13 <(echo "$base_groups") <(getent group | cut -d: -f1 | sort)); do
    groupdel "$name" || { say "cannot remove group $name"; return 1; }
  done
  rm -rf /etc/wheeltec* /var/lib/wheeltec* /run/wheeltec* /var/lib/private/wheeltec*
  systemctl daemon-reload
  journalctl --rotate --vacuum-time=1s >/dev/null 2>&1
}

install_package() {
  DEBIAN_FRONTEND=noninteractive dpkg -i "$SYSTEMD_UML_DEB" >/dev/null || { say "dpkg -i failed"; return 1; }
}

# run_suite NAME SECONDS: NAME.sh with its output labelled; its exit status (124: timed out).
# timeout(1) runs it in a process group of its own, which is killed once it ends.
run_suite() {
  ( timeout -k 5 "$2" bash "$HERE/$1.sh" </dev/null 2>&1 &
    leader=$!
    wait "$leader"
    status=$?
    kill -KILL -- "-$leader" 2>/dev/null
    exit "$status" ) | sed -u "s/^/[$1] /"
  return "${PIPESTATUS[0]}"
}

failed=()
results=()
for entry in "${suites[@]}"; do
  name=${entry%%:*} limit=${entry##*:}
  say "---- $name (time limit $limit s)"
  started=$(date +%s%N)
  if ! reset; then
    say "$name: FAILED (the reset before it failed)"
    failed+=("$name") results+=("$name FAILED (reset)")
    continue
  fi
  setup="reset $(ms_since "$started") ms"
  if [[ $name != lifecycle ]]; then
    installing=$(date +%s%N)
    if ! install_package; then
      say "$name: FAILED (dpkg -i before it failed)"
      failed+=("$name") results+=("$name FAILED (dpkg -i)")
      continue
    fi
    setup+=", dpkg -i $(ms_since "$installing") ms"
  fi
  say "$name: $setup"
  running=$(date +%s%N)
  run_suite "$name" "$limit"
  status=$?
  took="$(awk -v ms="$(ms_since "$running")" 'BEGIN { printf "%.1f", ms / 1000 }') s"
  case $status in
    0) verdict=passed ;;
    124) verdict="FAILED (timed out after $limit s)" ;;
    *) verdict="FAILED (exit $status)" ;;
  esac
  say "$name: $verdict in $took ($setup)"
  results+=("$name $verdict, $took")
  ((status == 0)) || failed+=("$name")
done

reset >/dev/null 2>&1
say "==== results"
for line in "${results[@]}"; do say "  $line"; done
if ((${#failed[@]})); then
  say "FAILED: ${failed[*]} (their FAIL: lines above are labelled [NAME])"
  exit 1
fi
say "all ${#suites[@]} suites passed"
