# Run at every build (cli/CMakeLists.txt): writes the commit the sources are at into
# OUT, touching it only when that changes, so that `epsray --version` and the stats
# JSON's provenance name the commit built rather than the one last configured.
cmake_minimum_required(VERSION 3.20)
# Only the sources' own checkout counts: an archive unpacked inside some other git
# repository must not take that repository's commit.
set(rc 1)
if(EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND git -C "${SOURCE_DIR}" describe --always --dirty
                  OUTPUT_VARIABLE commit RESULT_VARIABLE rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
endif()
if(NOT rc EQUAL 0 OR commit STREQUAL "")
  set(commit unknown)  # not a git checkout (a source archive), or no git
endif()
file(CONFIGURE OUTPUT "${OUT}" CONTENT "#define EPSRAY_COMMIT \"@commit@\"\n" @ONLY)
