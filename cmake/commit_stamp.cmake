# Writes the commit the sources are at into OUTPUT (a C++ #define), at build time, so that a
# binary never names a commit older than its code. "+changes" marks sources that differ from
# that commit. The file is rewritten only when its text changes (no rebuild otherwise).
execute_process(COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
if(failed OR NOT commit)
  set(commit "unknown")
else()
  # only the code: results/ and docs/ change without changing what the binary computes
  execute_process(COMMAND git diff --quiet HEAD -- core backends bench render shaders python
    CMakeLists.txt cmake
    WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE changed ERROR_QUIET)
  if(changed)
    set(commit "${commit}+changes")
  endif()
endif()
file(WRITE "${OUTPUT}.new" "#define CHAINMAIL_COMMIT \"${commit}\"\n")
file(COPY_FILE "${OUTPUT}.new" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.new")
