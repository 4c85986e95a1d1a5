# shellcheck shell=bash
# Starting User-Mode Linux, for scripts/vcan-run and scripts/systemd-uml.

# Prints the path of scripts/lib/uml_xstate_shim.c built as a preloadable library (built
# once per host and version of the file, in $TMPDIR or /tmp); fails without a C compiler.
# Debian 12's UML cannot start a process on hosts with AVX-512 or AMX without it (see the
# file), and it changes nothing where UML can.
uml_xstate_shim() {
    local source
    source="$(dirname "${BASH_SOURCE[0]}")/uml_xstate_shim.c"
    local hash
    hash=$(sha1sum < "$source" | cut -c1-16) || return 1
    local shim
    shim="${TMPDIR:-/tmp}/wheeltec-uml-xstate-shim-$hash-$(id -u).so"
    if [[ ! -f $shim ]]; then
        local built
        built=$(mktemp "$shim.XXXXXX") || return 1
        if ! cc -O2 -shared -fPIC -o "$built" "$source" -ldl >&2; then
            rm -f -- "$built"
            return 1
        fi
        mv -f -- "$built" "$shim"
    fi
    echo "$shim"
}

# linux.uml with ARGS, the shim preloaded when it can be built.
linux_uml() {
    local shim
    if shim=$(uml_xstate_shim); then
        LD_PRELOAD="$shim${LD_PRELOAD:+:$LD_PRELOAD}" linux.uml "$@"
    else
        linux.uml "$@"
    fi
}

# The directory of the UML kernel's modules (/usr/lib/uml/modules/VERSION/kernel): the
# running linux.uml's version when installed, else the first one there.
uml_module_dir() {
    local version
    version=$(linux.uml --version 2>/dev/null | tail -n 1)
    if [[ -n $version && -d /usr/lib/uml/modules/$version ]]; then
        echo "/usr/lib/uml/modules/$version/kernel"
        return
    fi
    local dirs=(/usr/lib/uml/modules/*/kernel)
    [[ -d ${dirs[0]} ]] && echo "${dirs[0]}"
}

# Stops the UML kernel started in the background as process group $uml_pid (TERM, then
# KILL after a second), with all of its host helper processes; clears uml_pid.
kill_uml() {
    [[ -n $uml_pid ]] || return 0
    kill -TERM -- "-$uml_pid" 2>/dev/null
    local _
    for _ in 1 2 3 4 5 6 7 8 9 10; do
        kill -0 -- "-$uml_pid" 2>/dev/null || break
        sleep 0.1
    done
    kill -KILL -- "-$uml_pid" 2>/dev/null
    uml_pid=
}
