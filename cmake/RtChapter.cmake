# rt_add_chapter(): one call makes a chapter's three targets.
#
#   rt_add_chapter(NUMBER 01 SLUG kernel_launch
#                  LESSON  first_kernel.cu ...   # -> library rt_ch01, alias rt::ch01
#                  MAIN    main.cpp              # -> executable ch01_kernel_launch
#                  DEPENDS rt::common            # the previous chapter's library
#                  TESTS   test_ch01.cpp ...)    # files in tests/01_kernel_launch -> test_ch01
#
# Build one chapter alone with: cmake --build <dir> --target ch01_kernel_launch
function(rt_add_chapter)
  cmake_parse_arguments(ARG "" "NUMBER;SLUG" "LESSON;MAIN;DEPENDS;TESTS" ${ARGN})
  set(lib rt_ch${ARG_NUMBER})
  set(exe ch${ARG_NUMBER}_${ARG_SLUG})

  add_library(${lib} STATIC ${ARG_LESSON})
  add_library(rt::ch${ARG_NUMBER} ALIAS ${lib})
  target_include_directories(${lib} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(${lib} PUBLIC ${ARG_DEPENDS} PRIVATE rt::options)
  set_target_properties(${lib} PROPERTIES CUDA_SEPARABLE_COMPILATION OFF)

  if(ARG_MAIN) # a chapter whose program is still to come has only its library and tests
    add_executable(${exe} ${ARG_MAIN})
    target_link_libraries(${exe} PRIVATE ${lib} rt::options)
    set_target_properties(${exe} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
  endif()

  if(RT_BUILD_TESTS AND ARG_TESTS)
    set(test_dir ${PROJECT_SOURCE_DIR}/tests/${ARG_NUMBER}_${ARG_SLUG})
    list(TRANSFORM ARG_TESTS PREPEND ${test_dir}/)
    rt_add_test_executable(test_ch${ARG_NUMBER} LABEL ch${ARG_NUMBER}
                           SOURCES ${ARG_TESTS} LIBRARIES ${lib})
  endif()
endfunction()

# rt_chapter_program_files(): where a chapter's program finds its files, and its tests find
# the program. The program gets the course's assets folder as RT_ASSETS_DIR (with MODELS also
# models/, where tools/get-models.sh puts the benchmark set, as RT_MODELS_DIR: the models are
# not part of the repository); the chapter's test executable, which runs the program and reads
# its JSON report, gets the program's path as RT_CHnn_PROGRAM and the assets folder, and is
# built after the program.
#
#   rt_chapter_program_files(NUMBER 09 SLUG wide_bvh MODELS)
function(rt_chapter_program_files)
  cmake_parse_arguments(ARG "MODELS" "NUMBER;SLUG" "" ${ARGN})
  set(exe ch${ARG_NUMBER}_${ARG_SLUG})
  set(test test_ch${ARG_NUMBER})
  target_compile_definitions(${exe} PRIVATE RT_ASSETS_DIR="${PROJECT_SOURCE_DIR}/assets")
  if(ARG_MODELS)
    target_compile_definitions(${exe} PRIVATE RT_MODELS_DIR="${PROJECT_SOURCE_DIR}/models")
  endif()
  if(TARGET ${test})
    target_compile_definitions(${test} PRIVATE
      RT_CH${ARG_NUMBER}_PROGRAM="$<TARGET_FILE:${exe}>"
      RT_ASSETS_DIR="${PROJECT_SOURCE_DIR}/assets")
    target_link_libraries(${test} PRIVATE nlohmann_json::nlohmann_json)
    add_dependencies(${test} ${exe})
  endif()
endfunction()

# rt_add_program(): one more program of a chapter, in <build>/bin beside the chapter's own.
# With TEST and DEFINE, that test executable gets the program's path as the macro DEFINE and
# is built after it (a test that runs the program).
#
#   rt_add_program(ch09_embree_compare SOURCES embree_compare.cpp LIBRARIES rt_ch09
#                  TEST test_ch09 DEFINE RT_CH09_EMBREE_PROGRAM)
function(rt_add_program name)
  cmake_parse_arguments(ARG "" "TEST;DEFINE" "SOURCES;LIBRARIES" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBRARIES} rt::options)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
  if(ARG_TEST AND TARGET ${ARG_TEST})
    target_compile_definitions(${ARG_TEST} PRIVATE ${ARG_DEFINE}="$<TARGET_FILE:${name}>")
    add_dependencies(${ARG_TEST} ${name})
  endif()
endfunction()

# rt_add_test_executable(): a Catch2 test executable whose test cases become CTest tests.
# Catch2 tags become CTest labels: [gpu] needs a CUDA device, [slow] takes long; every test
# also carries the executable's LABEL (ch01, common, ...), so `ctest -L ch01` runs one chapter.
function(rt_add_test_executable name)
  cmake_parse_arguments(ARG "" "LABEL" "SOURCES;LIBRARIES" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE rt_test_support ${ARG_LIBRARIES} rt::options)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  # --warn NoTests: a CTest entry whose name matches no test fails instead of passing empty
  # (a test name with an unmatched [ once made CMake fold dozens of names into one entry).
  # A test that ends in RT_SKIP (rt_skip.h) says "SKIPPED: ..." and counts as skipped.
  catch_discover_tests(${name} TEST_PREFIX "${ARG_LABEL}:" TEST_LIST ${name}_TESTS
                       EXTRA_ARGS --warn NoTests
                       PROPERTIES TIMEOUT 600 LABELS ${ARG_LABEL}
                                  SKIP_REGULAR_EXPRESSION "SKIPPED:")
  # Catch2's discovery cannot turn tags into labels, so CTest reads a second file after
  # Catch's own: it asks the executable which tests carry [gpu] and [slow] and labels them.
  set(label_file ${CMAKE_CURRENT_BINARY_DIR}/${name}_labels.cmake)
  file(GENERATE OUTPUT ${label_file} CONTENT
"set(RT_TEST_EXE \"$<TARGET_FILE:${name}>\")
set(RT_TEST_PREFIX \"${ARG_LABEL}:\")
set(RT_TEST_LABEL \"${ARG_LABEL}\")
include(\"${PROJECT_SOURCE_DIR}/cmake/RtCatchLabels.cmake\")
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${label_file})
endfunction()
