# Installation as a Debian tool (docs/install.md): the binary, the Slurm scripts, the docs and
# a man page generated from the program's own --help, and a .deb built by CPack whose
# dependencies are the Debian runtime packages the binary links (dpkg-shlibdeps).
include_guard(GLOBAL)
include(GNUInstallDirs)

install(TARGETS allanlot RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(PROGRAMS slurm/submit-lot slurm/lot-status slurm/lot-task.sbatch slurm/lot-merge.sbatch
        DESTINATION ${CMAKE_INSTALL_DATADIR}/allanlot/slurm)
# README.md links docs/*.md relatively, so both keep their places under the doc directory.
install(FILES README.md CHANGELOG.md LICENSE CITATION.cff DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
# Debian looks for the licence of a package in /usr/share/doc/<package>/copyright.
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)

# The man page is written by help2man from `allanlot --help`, `--version` and each command's
# --help (cmake/AllanlotManPage.cmake), so it cannot drift from the program. Without help2man
# (scripts/setup installs it) the page is left out with a message, not the whole build.
find_program(ALLANLOT_HELP2MAN help2man)
if(ALLANLOT_HELP2MAN)
  set(_man ${CMAKE_BINARY_DIR}/allanlot.1)
  add_custom_command(
    OUTPUT ${_man} ${_man}.gz
    COMMAND ${CMAKE_COMMAND} -DHELP2MAN=${ALLANLOT_HELP2MAN} -DALLANLOT=$<TARGET_FILE:allanlot>
            -DOUTPUT=${_man} -DWORKDIR=${CMAKE_BINARY_DIR}/man
            -P ${CMAKE_CURRENT_LIST_DIR}/AllanlotManPage.cmake
    DEPENDS allanlot ${CMAKE_CURRENT_LIST_DIR}/AllanlotManPage.cmake
    COMMENT "Writing the man page allanlot.1 with help2man")
  add_custom_target(allanlot_man ALL DEPENDS ${_man}.gz)
  install(FILES ${_man}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "help2man not found: the man page allanlot.1 is not built (scripts/setup)")
endif()

set(CPACK_PACKAGE_NAME allanlot)
set(CPACK_PACKAGE_VENDOR "The allanlot developers")
set(CPACK_PACKAGE_CONTACT "The allanlot developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Allan-variance noise characterization of inertial sensor lots and clocks")
set(CPACK_PACKAGE_DESCRIPTION
    "allanlot computes the Allan deviation family (ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV, TOTDEV)\
 with confidence intervals, the PSD and its cross-check, and fits the five-term noise model of\
 IMU gyroscopes and accelerometers and of clocks, for whole production lots; Slurm job arrays\
 for clusters.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The Python module (python/) imports numpy at run time; the command line needs neither.
if(ALLANLOT_BUILD_PYTHON)
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy")
endif()
include(CPack)
