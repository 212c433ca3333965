# tricot_embed_examples(TARGET FILE...): the files examples/FILE built into TARGET as text, so that an
# installed tricot needs no source tree (include/tricot/project/examples.hpp reads them). The build
# writes embedded_examples.cpp, one raw string literal per file, and writes it again when a file changes.
function(tricot_embed_examples target)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_examples.cpp)
  set(paths)
  foreach(f ${ARGN})
    list(APPEND paths ${PROJECT_SOURCE_DIR}/examples/${f})
  endforeach()
  string(REPLACE ";" "," files "${ARGN}")  # one argument through the custom command
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DROOT=${PROJECT_SOURCE_DIR}/examples -DFILES=${files} -DOUT=${out} -P
            ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    DEPENDS ${paths} ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    COMMENT "Embedding the demos' examples"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()

# cmake -P: writes OUT from the files FILES (comma-separated, relative to ROOT).
if(CMAKE_SCRIPT_MODE_FILE)
  set(delimiter "tricot_example")
  set(table "")
  string(REPLACE "," ";" files "${FILES}")
  foreach(f ${files})
    file(READ ${ROOT}/${f} text)
    string(FIND "${text}" ")${delimiter}\"" clash)
    if(NOT clash EQUAL -1)
      message(FATAL_ERROR "examples/${f} holds the raw string's delimiter )${delimiter}\"")
    endif()
    string(APPEND table "      {\"${f}\", R\"${delimiter}(${text})${delimiter}\"},\n")
  endforeach()
  file(WRITE ${OUT}
       "// Written by cmake/TricotEmbed.cmake from examples/ at build time: do not edit.\n"
       "#include \"tricot/project/examples.hpp\"\n\n"
       "namespace tricot::project {\n\n"
       "std::span<const ExampleFile> example_files() {\n"
       "  static constexpr ExampleFile files[] = {\n"
       "${table}"
       "  };\n"
       "  return files;\n"
       "}\n\n"
       "}  // namespace tricot::project\n")
endif()
