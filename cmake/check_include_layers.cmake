# Checks that includes run down the layers only: a file in a folder may
# include its own folder's headers and those of the folders listed before
# it (docs/architecture.md, "Layers"). Run by ctest:
#   cmake -DSOURCE_DIR=<repository> -P cmake/check_include_layers.cmake
set(layers core runtime compare media scene prepare io integrators render api testing apps)

set(violations "")
foreach(folder IN LISTS layers)
  list(FIND layers ${folder} rank)
  file(GLOB_RECURSE files ${SOURCE_DIR}/${folder}/*.h ${SOURCE_DIR}/${folder}/*.cpp)
  foreach(file IN LISTS files)
    file(STRINGS ${file} includes REGEX "^#include \"[a-z_]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^#include \"([a-z_]+)/.*" "\\1" included "${line}")
      list(FIND layers ${included} includedRank)
      if(includedRank GREATER rank)
        file(RELATIVE_PATH name ${SOURCE_DIR} ${file})
        list(APPEND violations "${name}: ${line} (${included} is above ${folder})")
      endif()
    endforeach()
  endforeach()
endforeach()

if(violations)
  list(JOIN violations "\n" text)
  message(FATAL_ERROR "includes that run up the layers:\n${text}")
endif()
list(JOIN layers " < " order)
message(STATUS "includes run down the layers: ${order}")
