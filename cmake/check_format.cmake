# ctest's `format` test: cmake -DSOURCE_DIR=<repo> -P cmake/check_format.cmake
# Fails when a C++ source under src/, cli/ or tests/ is not laid out as the project's
# .clang-format says (clang-format --dry-run -Werror), naming the files; skipped (exit 77) where
# clang-format is not installed (scripts/install-deps.sh installs it).
cmake_minimum_required(VERSION 3.25)
find_program(CLANG_FORMAT clang-format)
if(NOT CLANG_FORMAT)
  message("clang-format is not installed: the format check is skipped")
  cmake_language(EXIT 77)
endif()
file(GLOB_RECURSE sources ${SOURCE_DIR}/src/*.h ${SOURCE_DIR}/src/*.cpp ${SOURCE_DIR}/cli/*.h
     ${SOURCE_DIR}/cli/*.cpp ${SOURCE_DIR}/tests/*.h ${SOURCE_DIR}/tests/*.cpp)
execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${sources}
                WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE result ERROR_VARIABLE messages)
if(NOT result EQUAL 0)
  string(REGEX MATCHALL "[^\n]*: error:" lines "${messages}")
  set(files "")
  foreach(line ${lines})
    string(REGEX REPLACE ":[0-9]+:[0-9]+: error:$" "" file "${line}")
    list(APPEND files ${file})
  endforeach()
  list(REMOVE_DUPLICATES files)
  string(REPLACE ";" "\n  " files "${files}")
  message(FATAL_ERROR "not laid out as .clang-format says (run clang-format -i on them):\n  ${files}")
endif()
