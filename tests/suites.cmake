# puff_add_suites(TARGET LABEL COST TIMEOUT): one ctest test per GoogleTest suite of TARGET, named
# after the suite and running it in one process (`TARGET --gtest_filter=Suite.*`), labelled LABEL,
# with ctest's COST and a TIMEOUT in seconds for the whole suite.
#
# A suite's tests share a process, so what a suite sets up once (a GL context, a baked atlas) is made
# once; a process per test spent most of the unit tier's time loading libraries (docs/testing.md,
# "Tiers"). The suites are listed after each build, as gtest_discover_tests lists tests, by
# list_suites.cmake. To run one test: TARGET --gtest_filter=Suite.Test.
#
# Every test gets PUFF_GL=osmesa and LeakSanitizer's suppressions for Mesa (tests/lsan.supp).
function(puff_add_suites target label cost timeout)
  set(_list "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  set(_include "${CMAKE_CURRENT_BINARY_DIR}/${target}_include.cmake")
  string(REPLACE ";" "|" _unsanitized "${PUFF_UNSANITIZED_SUITES}")  # tiers.cmake
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -D "EXE=$<TARGET_FILE:${target}>" -D "OUT=${_list}" -D "LABEL=${label}"
            -D "UNSANITIZED=${_unsanitized}"
            -D "COST=${cost}" -D "TIMEOUT=${timeout}" -D "LSAN_SUPP=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp"
            -P "${CMAKE_CURRENT_SOURCE_DIR}/list_suites.cmake"
    BYPRODUCTS "${_list}" VERBATIM)
  file(WRITE "${_include}"
    "if(EXISTS \"${_list}\")\n"
    "  include(\"${_list}\")\n"
    "else()\n"
    "  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_include}")
endfunction()
