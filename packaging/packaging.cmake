# Debian packages (CPack DEB), included by the top-level CMakeLists.txt:
#   amb-firmware (component firmware): the controller board's service: amb-firmware, board
#     files in /usr/share/amb/boards, /etc/amb/amb-firmware.conf (conffile), the systemd unit,
#     maintainer scripts, man page. Built from the aarch64 cross build -> arm64.
#   amb-host (component host): the workstation tools amb-host and amb-plant. Host build -> amd64.
# `cmake --build BUILD --target package` (or scripts/package.sh) writes the .deb(s) of the
# components this build has; see docs/packaging.md.
include(GNUInstallDirs)

set(AMB_PKG_DIR ${CMAKE_CURRENT_LIST_DIR})
set(AMB_PKG_OUT ${PROJECT_BINARY_DIR}/packaging)
set(CMAKE_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)

# Debian wants man pages and changelogs compressed with gzip -9n (no name, no timestamp).
find_program(AMB_GZIP gzip REQUIRED)
set(AMB_PKG_GZ_OUTPUTS)
function(amb_pkg_gzip src dst)
  add_custom_command(OUTPUT ${dst}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${AMB_PKG_OUT}
    COMMAND ${AMB_GZIP} -9n -c ${src} > ${dst}
    DEPENDS ${src} VERBATIM)
  set(AMB_PKG_GZ_OUTPUTS ${AMB_PKG_GZ_OUTPUTS} ${dst} PARENT_SCOPE)
endfunction()
amb_pkg_gzip(${AMB_PKG_DIR}/man/amb-firmware.8 ${AMB_PKG_OUT}/amb-firmware.8.gz)
amb_pkg_gzip(${AMB_PKG_DIR}/man/amb-host.1 ${AMB_PKG_OUT}/amb-host.1.gz)
amb_pkg_gzip(${AMB_PKG_DIR}/man/amb-plant.1 ${AMB_PKG_OUT}/amb-plant.1.gz)
amb_pkg_gzip(${AMB_PKG_DIR}/changelog ${AMB_PKG_OUT}/changelog.Debian.gz)
add_custom_target(amb_package_docs ALL DEPENDS ${AMB_PKG_GZ_OUTPUTS})

# ---- amb-firmware (the executable's install rule is in firmware/CMakeLists.txt) ----------------
file(GLOB AMB_PKG_BOARDS ${PROJECT_SOURCE_DIR}/boards/*.toml)
install(FILES ${AMB_PKG_BOARDS} DESTINATION ${CMAKE_INSTALL_DATADIR}/amb/boards COMPONENT firmware)
# /etc and /lib/systemd are absolute on purpose: a Debian package's locations, not the prefix's.
install(FILES ${AMB_PKG_DIR}/amb-firmware.conf DESTINATION /etc/amb COMPONENT firmware)
install(FILES ${AMB_PKG_DIR}/amb-firmware.service DESTINATION /lib/systemd/system COMPONENT firmware)
install(FILES ${AMB_PKG_OUT}/amb-firmware.8.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man8 COMPONENT firmware)
install(FILES ${AMB_PKG_DIR}/copyright ${AMB_PKG_OUT}/changelog.Debian.gz
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/amb-firmware COMPONENT firmware)

# ---- amb-host (executables: host-tools/CMakeLists.txt) ------------------------------------------
install(FILES ${AMB_PKG_OUT}/amb-host.1.gz ${AMB_PKG_OUT}/amb-plant.1.gz
        DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT host)
install(FILES ${AMB_PKG_DIR}/copyright ${AMB_PKG_OUT}/changelog.Debian.gz
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/amb-host COMPONENT host)

# ---- CPack ---------------------------------------------------------------------------------------
# The cross build (no host tools) packages the board's service; a host build the host tools.
if(AMB_BUILD_HOST_TOOLS)
  set(AMB_PACKAGE_COMPONENTS_DEFAULT host)
else()
  set(AMB_PACKAGE_COMPONENTS_DEFAULT firmware)
endif()
set(AMB_PACKAGE_COMPONENTS ${AMB_PACKAGE_COMPONENTS_DEFAULT} CACHE STRING
    "CPack components to package: firmware (amb-firmware) and/or host (amb-host)")
# Package revision: scripts/package.sh --revision N; the target test builds an upgrade with it.
set(AMB_PACKAGE_RELEASE 1 CACHE STRING "Debian revision of the packages (VERSION-RELEASE)")

if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64)$")
  set(AMB_DEB_ARCH arm64)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(AMB_DEB_ARCH amd64)
else()
  set(AMB_DEB_ARCH ${CMAKE_SYSTEM_PROCESSOR})
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME amb-supervisor)
set(CPACK_PACKAGE_VENDOR "AMB supervisor project")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "AMB supervisor project <amb-supervisor@example.org>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES TRUE)
set(CPACK_OUTPUT_FILE_PREFIX ${PROJECT_BINARY_DIR}/dist)
set(CPACK_COMPONENTS_ALL ${AMB_PACKAGE_COMPONENTS})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE ${AMB_PACKAGE_RELEASE})
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${AMB_DEB_ARCH})
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://example.org/amb-supervisor")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION TRUE)

# Shared-library dependencies by hand: dpkg-shlibdeps does not run on the cross build's arm64
# binary from an amd64 host; the lists are the NEEDED entries of the binaries (readelf -d),
# versions from Debian 12 (the libc/libstdc++ of the build). scripts/package.sh checks that
# every NEEDED library of the packaged binaries is covered.
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_NAME amb-firmware)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_DEPENDS
    "libc6 (>= 2.34), libgcc-s1 (>= 3.0), libstdc++6 (>= 12), libfftw3-double3 (>= 3.3.5), libgpiod2 (>= 1.6), libmodbus5 (>= 3.1.6), init-system-helpers (>= 1.54~)")
set(CPACK_DEBIAN_FIRMWARE_PACKAGE_CONTROL_EXTRA
    ${AMB_PKG_DIR}/amb-firmware/conffiles ${AMB_PKG_DIR}/amb-firmware/postinst
    ${AMB_PKG_DIR}/amb-firmware/prerm ${AMB_PKG_DIR}/amb-firmware/postrm)
# Synopsis, then the extended description: CPack indents each line by one space and turns an
# empty line into " ." (Debian policy 5.6.13); lines stay under 80 columns.
set(CPACK_COMPONENT_FIRMWARE_DESCRIPTION "real-time supervisor service of an AMB controller board
amb-firmware levitates the rotor of an active-magnetic-bearing rig, watches
for trouble, captures rotor-drop events, keeps the auxiliary-bearing wear
record and serves its register map over Modbus TCP. The field bus is
SocketCAN, the discrete lines a GPIO chip (libgpiod).

The package runs it as the systemd service amb-firmware.service (SCHED_FIFO
loop, locked memory, CPU affinity, watchdog). The board file and the data
directory are set in /etc/amb/amb-firmware.conf; the shipped board files are
in /usr/share/amb/boards.")

set(CPACK_DEBIAN_HOST_PACKAGE_NAME amb-host)
set(CPACK_DEBIAN_HOST_PACKAGE_SECTION science)
set(CPACK_DEBIAN_HOST_PACKAGE_SHLIBDEPS ON)
set(CPACK_COMPONENT_HOST_DESCRIPTION "host tools of the AMB supervisor: drop events, fits, wear records
amb-host downloads the rotor-drop events captured by an amb-firmware board,
fits the multibody drop model, traces residuals to missing effects, writes
reports and writes the auxiliary-bearing wear record back to the board.

amb-plant emulates the rig's sensor and amplifier nodes on the CAN field bus
for hardware-in-the-loop bench tests of a board.")

# Immediate binding (lintian: hardening-no-bindnow): a link option only, no recompilation.
foreach(t amb-firmware amb-host amb-plant)
  if(TARGET ${t})
    target_link_options(${t} PRIVATE -Wl,-z,relro -Wl,-z,now)
  endif()
endforeach()

include(CPack)
