# cmake -P script: copies shader INPUT to OUTPUT with every `#include "NAME.glsl"` replaced by
# the text of NAME.glsl from the same directory (one level: .glsl pieces include nothing).
# GLSL ES has no #include; shared pieces (the Lafortune BRDF, the SH basis) live once in a
# .glsl file and every stage that needs them is validated and embedded expanded.
get_filename_component(dir "${INPUT}" DIRECTORY)
file(READ "${INPUT}" text)
string(REGEX MATCHALL "#include \"[A-Za-z0-9_]+\\.glsl\"" includes "${text}")
list(REMOVE_DUPLICATES includes)
foreach(directive IN LISTS includes)
  string(REGEX REPLACE "#include \"([A-Za-z0-9_]+\\.glsl)\"" "\\1" piece "${directive}")
  if(NOT EXISTS "${dir}/${piece}")
    message(FATAL_ERROR "${INPUT}: #include of missing ${piece}")
  endif()
  file(READ "${dir}/${piece}" pieceText)
  string(REPLACE "${directive}" "${pieceText}" text "${text}")
endforeach()
file(WRITE "${OUTPUT}.tmp" "${text}")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
