# A Debian package of the programs and configs (CPack): `cpack -G DEB` in a build folder, or
# tests/deb-check.sh, which builds it portable and checks it. What goes in is what
# `cmake --install` installs (the install() rules beside each target and in deploy/).
#
# Build it with -DSRICS_NATIVE=OFF: with -march=native the programs only run on CPUs with this
# host's vector instructions (the file name then says "native" so it is not handed around).
# The networks' matrix products still use the installing host's widest vectors: oneDNN
# (libdnnl2, found by dpkg-shlibdeps) chooses its kernels at run time (common/nn/gemm.h).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME srics-dds)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "SRICS-DDS")
set(CPACK_PACKAGE_CONTACT "SRICS-DDS maintainers <srics-dds@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "SRICS distributed actor-learner RL over Cyclone DDS: srics, srics-actor, srics-learner, srics-graph, srics-monitor")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# the shared libraries the programs link (Cyclone DDS, MuJoCo, yaml-cpp, spdlog, libpng, EGL)
# come from dpkg-shlibdeps; the tools the run folder's plots and graph pictures call do not
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "gnuplot-nox | gnuplot, graphviz, libegl-mesa0, libgl1-mesa-dri")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "ffmpeg")
if(SRICS_NATIVE)
  set(CPACK_DEBIAN_FILE_NAME "${CPACK_PACKAGE_NAME}_${PROJECT_VERSION}_native-only.deb")
else()
  set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # srics-dds_0.1.0_amd64.deb
endif()
include(CPack)
