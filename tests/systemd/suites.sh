#!/usr/bin/env bash
# Runs several scripts of the systemd suite in one User-Mode Linux session, one after
# another, each from the state a session of its own would give it: booting systemd costs
# more than most suites' checks (scripts/systemd-uml prints it), so the session boots once.
# Run as root inside scripts/systemd-uml --no-install:
#
#   suites.sh NAME:SECONDS...
#
# Each NAME.sh (this directory) runs with a time limit of SECONDS and its output labelled
# "[NAME] ", from the state a fresh session would give it. lifecycle, which installs the
# package itself, gets the machine as booted: before it the package is purged, and the
# users and groups made since the boot (the package's wheeltec too), the bridges' /etc and
# /var/lib directories and the journal are removed. Every other suite gets the package
# freshly installed with dpkg -i, as systemd-uml installs it: after the one install (the
# first suite that needs it) the state the suites change is saved, and before each later
# suite restored: the services stopped and disabled, the users and groups made since
# removed, the account files, /etc/wheeltecd (the conffile) and the package's state put
# back, /etc/wheeltec-*, /var/lib/wheeltec* (the latch's state file too) and /run/wheeltec*
# emptied, the journal emptied. A suite that changes the installed package gets a purge and
# a new install instead. A suite's leftover processes (its process group) are killed when it
# ends. $WHEELTEC_SYSTEMD_ONLY (names, space- or comma-separated) runs only those. Exits 1
# if any suite failed, naming each.
set -uo pipefail
: "${SYSTEMD_UML_DEB:?the package to install (run inside scripts/systemd-uml)}"

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
readonly HERE
readonly PACKAGE=wheeltec-gateway
readonly UNITS=(wheeltec-web.service wheeltec-mqtt.service wheeltec-ros2.service
                wheeltec-record.service wheeltecd.service)
say() { echo "systemd-suites: $*"; }
ms_since() { echo $((($(date +%s%N) - $1) / 1000000)); }

only=" ${WHEELTEC_SYSTEMD_ONLY:-} "
only=${only//,/ }
suites=()
for entry in "$@"; do
  [[ $entry =~ ^[a-z0-9-]+:[0-9]+$ ]] || { say "bad suite '$entry' (NAME:SECONDS)"; exit 2; }
  [[ -f $HERE/${entry%%:*}.sh ]] || { say "no suite ${entry%%:*} ($HERE/${entry%%:*}.sh)"; exit 2; }
  [[ $only == "  " || $only == *" ${entry%%:*} "* ]] && suites+=("$entry")
done
((${#suites[@]})) || { say "no suite to run"; exit 2; }

work=$(mktemp -d /tmp/systemd-suites.XXXXXX)
trap 'rm -rf -- "$work"' EXIT
# What a suite may change that a fresh install has: the account files and the conffile.
readonly SAVED=(etc/passwd etc/group etc/shadow etc/gshadow etc/subuid etc/subgid etc/wheeltecd)
user_names() { getent passwd | cut -d: -f1 | sort; }
group_names() { getent group | cut -d: -f1 | sort; }
package_state() { dpkg-query -W -f='${db:Status-Status} ${Version}' "$PACKAGE" 2>/dev/null; }
installed() { [[ $(package_state) == installed* ]]; }
# The users and groups of the booted machine.
user_names >"$work/boot.users"
group_names >"$work/boot.groups"
saved_state=

# remove_accounts USERS GROUPS: removes the users and groups not listed in the files, with
# their processes, homes and mail (userdel, groupdel).
remove_accounts() {
  local name
  for name in $(comm -13 "$1" <(user_names)); do
    ps -o pid= -u "$name" 2>/dev/null | xargs -r kill -KILL 2>/dev/null
    userdel -r -f "$name" >/dev/null 2>&1  # exit 12 for a home that is not there (/nonexistent)
    ! getent passwd "$name" >/dev/null || { say "cannot remove user $name"; return 1; }
  done
  for name in $(comm -13 "$2" <(group_names)); do
    groupdel "$name" || { say "cannot remove group $name"; return 1; }
  done
}
# leave_accounts USERS: the processes, homes and mail of the users not listed in the file
# gone; the account files themselves are restored from the saved state afterwards
# (faster than a userdel each in User-Mode Linux).
leave_accounts() {
  local name home
  for name in $(comm -13 "$1" <(user_names)); do
    home=$(getent passwd "$name" | cut -d: -f6)
    ps -o pid= -u "$name" 2>/dev/null | xargs -r kill -KILL 2>/dev/null
    [[ $home == /home/?* ]] && rm -rf -- "$home"
    rm -f -- "/var/mail/$name"
  done
}
# timed WHAT COMMAND...: runs COMMAND, adding "WHAT N ms" to $steps (the setup's breakdown).
steps=
timed() {
  local what=$1 begun status
  shift
  begun=$(date +%s%N)
  "$@"
  status=$?
  steps+="${steps:+, }$what $(ms_since "$begun") ms"
  return "$status"
}
# stop_services: the package's services stopped, their failed state and restart counts
# reset, and disabled: the links `systemctl enable` made removed, as `systemctl disable`
# does but without its daemon-reload (seconds in User-Mode Linux): is-enabled reads the
# links, and the session never starts multi-user.target, whose Wants= systemd keeps.
stop_services() {
  systemctl stop "${UNITS[@]}" 2>/dev/null
  systemctl reset-failed "${UNITS[@]}" 2>/dev/null
  find /etc/systemd/system -name 'wheeltec*' -type l -delete 2>/dev/null
}
forget_runtime() {
  rm -rf /etc/wheeltec-* /var/lib/wheeltec* /run/wheeltec* /var/lib/private/wheeltec*
  journalctl --rotate --vacuum-time=1s >/dev/null 2>&1
}

# as_booted: the package purged, the machine as booted (nothing to do before the first suite).
booted=1
as_booted() {
  ((booted)) && return 0
  timed stop stop_services
  if [[ -n $(package_state) && $(package_state) != not-installed* ]]; then
    timed "dpkg -P" env DEBIAN_FRONTEND=noninteractive dpkg -P "$PACKAGE" >/dev/null ||
      { say "dpkg -P $PACKAGE failed"; return 1; }
  fi
  timed accounts remove_accounts "$work/boot.users" "$work/boot.groups" || return 1
  rm -rf /etc/wheeltecd
  timed forget forget_runtime
  saved_state=
  booted=1
}
# freshly_installed: the state right after dpkg -i on the booted machine.
freshly_installed() {
  if [[ -n $saved_state && $(package_state) == "$saved_state" ]]; then
    timed stop stop_services
    timed accounts leave_accounts "$work/installed.users"
    rm -rf /etc/wheeltecd
    timed files tar -C / -xpf "$work/installed.tar" || { say "cannot restore the saved state"; return 1; }
    timed forget forget_runtime
    return
  fi
  as_booted || return 1
  timed "dpkg -i" env DEBIAN_FRONTEND=noninteractive dpkg -i "$SYSTEMD_UML_DEB" >/dev/null ||
    { say "dpkg -i failed"; return 1; }
  booted=0
  user_names >"$work/installed.users"
  group_names >"$work/installed.groups"
  tar -C / -cpf "$work/installed.tar" --ignore-failed-read "${SAVED[@]}" 2>/dev/null
  saved_state=$(package_state)
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
  steps=
  if [[ $name == lifecycle ]]; then state=as_booted; else state=freshly_installed; fi
  if [[ $state == as_booted ]]; then setup="the machine as booted"
  elif [[ -n $saved_state && $(package_state) == "$saved_state" ]]; then setup="the installed state restored"
  else setup="freshly installed"; fi
  if ! "$state"; then
    say "$name: FAILED (could not prepare $setup)"
    failed+=("$name") results+=("$name FAILED (setup)")
    continue
  fi
  setup+=" in $(ms_since "$started") ms${steps:+ ($steps)}"
  say "$name: $setup"
  running=$(date +%s%N)
  run_suite "$name" "$limit"
  status=$?
  booted=0
  took="$(awk -v ms="$(ms_since "$running")" 'BEGIN { printf "%.1f", ms / 1000 }') s"
  case $status in
    0) verdict=passed ;;
    124) verdict="FAILED (timed out after $limit s)" ;;
    *) verdict="FAILED (exit $status)" ;;
  esac
  say "$name: $verdict in $took (before it: $setup)"
  results+=("$name $verdict in $took (before it: $setup)")
  ((status == 0)) || failed+=("$name")
done

say "==== results"
for line in "${results[@]}"; do say "  $line"; done
if ((${#failed[@]})); then
  say "FAILED: ${failed[*]} (their FAIL: lines above are labelled [NAME])"
  exit 1
fi
say "all ${#suites[@]} suites passed"
