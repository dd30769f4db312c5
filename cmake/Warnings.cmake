# Warnings apply to the project's own targets only, never to dependencies.
function(caustica_target_defaults target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
    -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough
    # Vulkan structs are written "VkFooInfo info{VK_STRUCTURE_TYPE_FOO_INFO};": the rest is zeroed on purpose.
    -Wno-missing-field-initializers)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC 12 reports "literal" + std::string as overlapping memcpy at -O3 (GCC bug 105329).
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(CAUSTICA_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Sanitizers are global so that static libraries and the executables linking them agree.
# -O1, as the sanitizers' own documentation advises: at -O0 the host-side work of the suite (the
# editor model's edits, the photon reference, image comparisons) ran 10 to 40 times slower than in
# Release; assertions stay on (the build type is Debug).
if(CAUSTICA_SANITIZE)
  add_compile_options(-O1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Fuzzing (clang): every library gets libFuzzer's coverage instrumentation; the fuzz targets link
# the fuzzer itself (tests/fuzz).
if(CAUSTICA_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "CAUSTICA_FUZZ needs clang (CXX=clang++)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
