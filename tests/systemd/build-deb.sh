#!/usr/bin/env bash
# The systemd suite's fixture: builds the project's .deb with cpack in BUILD_DIR, into
# OUT_DIR, and links it as OUT_DIR/wheeltec-gateway.deb for the tests.
#   build-deb.sh BUILD_DIR OUT_DIR
set -euo pipefail
build_dir=$1 out_dir=$2
rm -rf -- "$out_dir"
mkdir -p "$out_dir"
(cd "$build_dir" && cpack -G DEB -B "$out_dir")
debs=("$out_dir"/wheeltec-gateway_*.deb)
[[ -f ${debs[0]} ]] || { echo "build-deb: cpack made no package" >&2; exit 1; }
ln -sf "$(basename "${debs[0]}")" "$out_dir/wheeltec-gateway.deb"
echo "package: ${debs[0]} ($(stat -c %s "${debs[0]}") bytes)"
