# shellcheck shell=bash
# Shared steps of scripts/test.sh and scripts/demo.sh: install the Debian 12 build and
# run-time dependencies when some are missing, then configure and build.
# Sourced, not executed. Needs REPO_ROOT set by the caller.

# What building the programs needs.
readonly WHEELTEC_BUILD_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libboost-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libcli11-dev libsystemd-dev
  libmosquitto-dev libssl-dev
  cyclonedds-dev cyclonedds-tools  # wheeltec-ros2's DDS, and idlc for its messages
  ccache  # CMakeLists.txt compiles through it when installed
  libzstd-dev zlib1g-dev  # the MCAP writer (mcap/): zstd-compressed chunks, zlib's CRC32
)
# What running them on a virtual CAN interface needs (the demo and the vcan tests):
# scripts/vcan-run, natively or inside User-Mode Linux.
readonly WHEELTEC_VCAN_PACKAGES=(can-utils iproute2 kmod user-mode-linux
  libjs-dygraphs)  # the plotting library that wheeltec-web serves to its page
# What only the tests need: GoogleTest, and for the systemd suite (tests/systemd,
# scripts/systemd-uml) systemd as PID 1 in UML, cpack's .deb installed with dpkg, users
# made with useradd/usermod, runuser, jq.
readonly WHEELTEC_TEST_PACKAGES=(libgtest-dev systemd dpkg-dev adduser passwd util-linux jq
  mosquitto mosquitto-clients openssl  # the broker, its clients and TLS certificates of the wheeltec-mqtt suites
  curl  # HTTP requests of the systemd suite of wheeltec-web
  chromium  # wheeltec-web's browser suite
  python3-aiohttp  # the Python Foxglove server that the bench smoke's wheeltec-web benchmark compares with (bench/web/aiohttp_foxglove.py)
  libfastrtps-dev fastddsgen  # Fast DDS, ROS 2's default middleware: the ros2 suite's independent ROS 2 side
  python3-pytest python3-mypy python3-exceptiongroup python3-tomli)  # the Python client's suite; the last two let Debian's pytest run under Python 3.9

# What the stages that build beside ctest need (scripts/test.sh): clang for the sanitizer and
# fuzzing builds (20-sanitizers.sh, 30-fuzz.sh), and the arm64 cross toolchain, its :arm64
# libraries and qemu (60-arm64.sh; Boost's headers are multi-arch "same" and needed as :arm64
# for its arm64 CMake config files, the header-only nlohmann-json3-dev and libcli11-dev come
# from the host). install_dependencies installs them before any test starts: the systemd
# suite's sessions see this machine's package database, where an install under way would
# show as an interrupted one.
readonly WHEELTEC_CLANG_PACKAGES=(clang-14 libclang-rt-14-dev)
readonly WHEELTEC_ARM64_PACKAGES=(crossbuild-essential-arm64 qemu-user file
  libboost-dev:arm64 libspdlog-dev:arm64 libfmt-dev:arm64 libgtest-dev:arm64 libsystemd-dev:arm64)

# Prints the packages among the arguments that are not installed.
missing_packages() {
  local package status native
  native=$(dpkg --print-architecture)
  for package in "$@"; do
    if [[ $package == *:* ]]; then
      status=$(dpkg-query -W -f='${db:Status-Status}' "$package" 2>/dev/null) || status=
      [[ $status == installed ]] || echo "$package"
    else
      # A name without an architecture is the native package (or an architecture-independent
      # one); the arm64 stage installs some of them for arm64 too.
      dpkg-query -W -f='${db:Status-Status} ${Architecture}\n' "$package" 2>/dev/null |
        grep -qE "^installed ($native|all)\$" || echo "$package"
    fi
  done
}

# Runs a command as root: directly when we are, else through sudo.
as_root() {
  if [[ $(id -u) -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

# Installs those of the given Debian packages that are missing, with apt-get (through
# sudo unless we are root). Test stages call it for what only they need.
install_packages() {
  if ! command -v dpkg-query >/dev/null 2>&1; then
    echo "setup: not a Debian system; install the equivalents of: $*" >&2
    return 0
  fi
  local missing
  mapfile -t missing < <(missing_packages "$@")
  if [[ ${#missing[@]} -eq 0 ]]; then
    return 0
  fi
  if [[ $(id -u) -ne 0 ]] && ! command -v sudo >/dev/null 2>&1; then
    echo "setup: missing packages (${missing[*]}) and no sudo; install them as root" >&2
    return 1
  fi
  echo "setup: installing ${missing[*]}"
  as_root apt-get update
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
}

# Lets dpkg install :arm64 packages (the arm64 stage's libraries).
add_arm64_architecture() {
  dpkg --print-foreign-architectures | grep -qx arm64 && return 0
  echo "setup: adding the arm64 architecture to dpkg"
  as_root dpkg --add-architecture arm64
  as_root apt-get update
}

# The programs' build and vcan packages; with "tests", the tests' and the test stages' too.
install_dependencies() {
  local packages=("${WHEELTEC_BUILD_PACKAGES[@]}" "${WHEELTEC_VCAN_PACKAGES[@]}")
  if [[ ${1:-} == tests ]]; then
    add_arm64_architecture
    packages+=("${WHEELTEC_TEST_PACKAGES[@]}" "${WHEELTEC_CLANG_PACKAGES[@]}" "${WHEELTEC_ARM64_PACKAGES[@]}")
    # wheeltec-web's suite runs npm's Foxglove client on node, and the MCAP writer's suite
    # npm's MCAP readers: Debian's nodejs, and its npm unless the nodejs already installed
    # brings one of its own.
    packages+=(nodejs)
    command -v npm >/dev/null 2>&1 || packages+=(npm)
  fi
  install_packages "${packages[@]}"
}

# ccache keeps what was compiled. Paths under this clone are hashed relative to it, so that a
# build of another clone of the same source (a CI run after a session) can reuse it.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$REPO_ROOT}
export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-true}

# How these scripts configure the build trees they make from scratch (the test command's,
# its stages', the demo's). A unity build: the sources of a target are compiled in batches
# of 16, so that each batch parses the headers and instantiates their templates once (a
# quarter of the processor time of file by file). RelWithDebInfo's debug information as
# line tables only: backtraces keep function names and lines, and full debug information
# costs a third more. A developer's own tree builds file by file unless configured so.
readonly WHEELTEC_FRESH_TREE_OPTIONS=(-DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG")

# Configures a fresh build directory ($BUILD_DIR, default build/) and builds the given
# targets, or everything when none are given.
configure_and_build() {
  BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
  local build_type=${CMAKE_BUILD_TYPE:-RelWithDebInfo}
  local jobs=${BUILD_JOBS:-$(nproc 2>/dev/null || echo 2)}
  local targets=()
  (($# == 0)) || targets=(--target "$@")
  rm -rf -- "$BUILD_DIR"
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" "${WHEELTEC_FRESH_TREE_OPTIONS[@]}" \
    -DWHEELTEC_BUILD_TESTS="${WHEELTEC_BUILD_TESTS:-ON}" \
    -DWHEELTEC_BUILD_BENCHMARKS="${WHEELTEC_BUILD_BENCHMARKS:-ON}"
  cmake --build "$BUILD_DIR" -j "$jobs" "${targets[@]}"
}
