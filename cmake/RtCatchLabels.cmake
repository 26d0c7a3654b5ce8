# Read by CTest (not CMake): labels the Catch2 tests of RT_TEST_EXE that carry the tags [gpu]
# and [slow], so `ctest -LE gpu` leaves out the tests that need a CUDA device.
cmake_policy(VERSION 3.25) # CTest reads test files under old policies
if(NOT EXISTS "${RT_TEST_EXE}")
  return()
endif()
set(rt_all_tagged "")
foreach(rt_tag gpu slow)
  # Catch2 v2 lists bare names with --list-test-names-only; v3 with --list-tests -v quiet.
  execute_process(COMMAND "${RT_TEST_EXE}" "[${rt_tag}]" --list-test-names-only
                  OUTPUT_VARIABLE rt_out ERROR_VARIABLE rt_err RESULT_VARIABLE rt_rc)
  if(rt_err MATCHES "Unrecognised token|unrecognised")
    execute_process(COMMAND "${RT_TEST_EXE}" "[${rt_tag}]" --list-tests --verbosity quiet
                    OUTPUT_VARIABLE rt_out RESULT_VARIABLE rt_rc)
  endif()
  string(REPLACE "\n" ";" rt_names "${rt_out}")
  list(FILTER rt_names EXCLUDE REGEX "^[ \t]*$")
  set(rt_${rt_tag}_names ${rt_names})
  list(APPEND rt_all_tagged ${rt_names})
endforeach()
list(REMOVE_DUPLICATES rt_all_tagged)
foreach(rt_name IN LISTS rt_all_tagged)
  set(rt_labels ${RT_TEST_LABEL})
  foreach(rt_tag gpu slow)
    if(rt_name IN_LIST rt_${rt_tag}_names)
      list(APPEND rt_labels ${rt_tag})
    endif()
  endforeach()
  set_tests_properties("${RT_TEST_PREFIX}${rt_name}" PROPERTIES LABELS "${rt_labels}")
endforeach()
