# Writes OUT, a C++ source defining `const char* NAME()` that returns the
# text of IN (the report viewer's bundled script, made at build time).
file(READ "${IN}" text)
string(FIND "${text}" ")PLTEXT\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter")
endif()
file(WRITE "${OUT}" "// Generated from ${IN} by cmake/embed_text.cmake.\nnamespace pl {\nconst char* ${NAME}() {\n    return R\"PLTEXT(${text})PLTEXT\";\n}\n}  // namespace pl\n")
