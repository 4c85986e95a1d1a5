# Install rules (FHS places under CMAKE_INSTALL_PREFIX, /etc for the configuration) and
# the Debian package: `cmake --install BUILD` or `cpack -G DEB` in BUILD.
# The three programs install themselves (install(TARGETS) in their directories).
include(GNUInstallDirs)

set(WHEELTEC_SYSTEMD_UNIT_DIR "lib/systemd/system" CACHE STRING "systemd unit directory, relative to the prefix")
set(WHEELTEC_NETWORKD_DIR "lib/systemd/network" CACHE STRING "systemd-networkd directory, relative to the prefix")
set(WHEELTEC_UDEV_RULES_DIR "lib/udev/rules.d" CACHE STRING "udev rules directory, relative to the prefix")
set(WHEELTEC_DOC_DIR "${CMAKE_INSTALL_DATADIR}/doc/wheeltec-gateway")

install(FILES systemd/wheeltecd.service DESTINATION ${WHEELTEC_SYSTEMD_UNIT_DIR})
# The optional programs (each built where its libraries are found), their units and man pages.
set(WHEELTEC_MAN_PAGES man/wheeltecd.8 man/wheeltecctl.1 man/wheeltec-emu.1)
foreach(program IN ITEMS wheeltec-mqtt wheeltec-web wheeltec-ros2 wheeltec-record)
  if(TARGET ${program})
    install(FILES systemd/${program}.service DESTINATION ${WHEELTEC_SYSTEMD_UNIT_DIR})
    list(APPEND WHEELTEC_MAN_PAGES man/${program}.1)
  endif()
endforeach()
install(FILES systemd/80-wheeltec-can.network DESTINATION ${WHEELTEC_NETWORKD_DIR})
# The serial link: names the controller's USB cable /dev/wheeltec_controller for the group
# wheeltec (/usr/lib/udev/rules.d/ in the package; udev reads /usr/local/lib/udev/rules.d/ too).
install(FILES systemd/60-wheeltec-controller.rules DESTINATION ${WHEELTEC_UDEV_RULES_DIR})
# Absolute: the unit and the daemon's default look for /etc/wheeltecd/wheeltecd.json.
set(WHEELTEC_CONFIG_DIR "/etc/wheeltecd" CACHE PATH "directory of wheeltecd.json")
# The installed configuration is config/wheeltecd.json (every key at its built-in default)
# but for one key: api.control_groups lets the group `wheeltec` drive, so that
# `sudo usermod -aG wheeltec $USER` is all a new owner needs (docs/deploy.md).
install(FILES packaging/wheeltecd.json DESTINATION ${WHEELTEC_CONFIG_DIR})

# Man pages and changelog compressed as Debian wants them (gzip -n: reproducible).
find_program(GZIP_PROGRAM gzip REQUIRED)
set(WHEELTEC_COMPRESSED_FILES)
# wheeltec_gzip(SOURCE SUBDIR DESTINATION): SOURCE (relative to the source tree) as
# BUILD/SUBDIR/NAME.gz, installed into DESTINATION.
function(wheeltec_gzip source subdir destination)
  get_filename_component(name ${source} NAME)
  set(compressed ${PROJECT_BINARY_DIR}/${subdir}/${name}.gz)
  add_custom_command(OUTPUT ${compressed}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/${subdir}
    COMMAND ${GZIP_PROGRAM} -9nc ${PROJECT_SOURCE_DIR}/${source} > ${compressed}
    DEPENDS ${PROJECT_SOURCE_DIR}/${source} VERBATIM)
  set(WHEELTEC_COMPRESSED_FILES ${WHEELTEC_COMPRESSED_FILES} ${compressed} PARENT_SCOPE)
  install(FILES ${compressed} DESTINATION ${destination})
endfunction()
foreach(page IN LISTS WHEELTEC_MAN_PAGES)
  string(REGEX REPLACE ".*\\.([0-9])$" "\\1" section ${page})
  wheeltec_gzip(${page} man ${CMAKE_INSTALL_MANDIR}/man${section})
endforeach()
# changelog.gz is the package's (Debian format); CHANGELOG.md.gz the project's.
foreach(source IN ITEMS packaging/debian/changelog CHANGELOG.md)
  wheeltec_gzip(${source} doc ${WHEELTEC_DOC_DIR})
endforeach()
add_custom_target(wheeltec_compressed_docs ALL DEPENDS ${WHEELTEC_COMPRESSED_FILES})

# The Python client (`import wheeltec`, docs/python.md): pure Python, for Debian's python3,
# which reads /usr/lib/python3/dist-packages whatever its minor version.
set(WHEELTEC_PYTHON_DIR "lib/python3/dist-packages" CACHE STRING "directory of the Python package wheeltec, relative to the prefix")
install(DIRECTORY python/wheeltec DESTINATION ${WHEELTEC_PYTHON_DIR}
        FILES_MATCHING PATTERN "*.py" PATTERN "py.typed" PATTERN "__pycache__" EXCLUDE)

install(FILES packaging/debian/copyright README.md DESTINATION ${WHEELTEC_DOC_DIR})
install(DIRECTORY docs/ DESTINATION ${WHEELTEC_DOC_DIR} FILES_MATCHING PATTERN "*.md")

# Debian package.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME wheeltec-gateway)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "wheeltec-gateway developers <dev@wheeltec-gateway.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "WHEELTEC robot chassis gateway (CAN or serial to JSON-RPC)")
set(CPACK_PACKAGE_DESCRIPTION "wheeltecd drives a WHEELTEC robot chassis over SocketCAN or the
controller's USB serial cable and serves JSON-RPC 2.0 to local clients over a
Unix socket, with a systemd service that runs it as the unprivileged user
wheeltec and a udev rule that names the vendor's serial cable
/dev/wheeltec_controller. wheeltecctl reads status and telemetry and drives
the robot from the command line; wheeltec-emu emulates the chassis controller
on a virtual CAN interface or a pseudo-terminal; wheeltec-mqtt bridges the
robot to an MQTT broker for a fleet; wheeltec-web serves a live view (plots,
odometry, joystick) to browsers and to Foxglove; wheeltec-ros2 publishes the
robot as ROS 2 topics (odom, imu, tf, diagnostics; cmd_vel in) over Cyclone
DDS, with no ROS installed; wheeltec-record is the black box, writing the
minute around each incident to an MCAP file for Foxglove (the bridges' and the
recorder's services are installed disabled). The Python package wheeltec
(import wheeltec) is the daemon's client for scripts.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# libjs-dygraphs: wheeltec-web serves its plotting library from /usr/share/javascript;
# python3: the Python client.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, libjs-dygraphs, python3")
# wheeltec-ros2 links Debian's Cyclone DDS (libddsc.so.0debian, from cyclonedds-dev);
# shlibdeps finds it too, but the package names it as the version the bridge was checked
# against (0.10.2: XCDR1 without type information, as rmw_cyclonedds).
if(TARGET wheeltec-ros2)
  string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS ", libddsc0debian (>= 0.10.2)")
endif()
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "can-utils, iproute2")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
  ${PROJECT_SOURCE_DIR}/packaging/debian/conffiles
  ${PROJECT_SOURCE_DIR}/packaging/debian/postinst
  ${PROJECT_SOURCE_DIR}/packaging/debian/prerm
  ${PROJECT_SOURCE_DIR}/packaging/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
