# Warnings apply to the project's own targets only, never to dependencies.
function(caustica_target_defaults target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
    -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough
    # Vulkan structs are written "VkFooInfo info{VK_STRUCTURE_TYPE_FOO_INFO};": the rest is zeroed on purpose.
    -Wno-missing-field-initializers)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC 12 reports "literal" + std::string as overlapping memcpy at -O3 (GCC bug 105329), and
    # -Wnull-dereference, which it checks after inlining, reports paths through nlohmann's JSON that
    # cannot happen (basic_json::m_type of a null `this`) in unity files at -O2 and -O3. Clang (the
    # fuzz build) keeps -Wnull-dereference.
    target_compile_options(${target} PRIVATE -Wno-restrict -Wno-null-dereference)
  endif()
  if(CAUSTICA_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  # Under the sanitizers the libraries, where the suite's host-side work runs, are built at -O1, as
  # the sanitizers' documentation advises: at -O0 the editor model's edits and the photon reference
  # ran 10 to 40 times slower than in Release (and with the device and viewer libraries at -O0 the
  # viewer and editor tests took 15% longer, the build no less). Tests and tools stay at -O0, which
  # compiles in about half the time.
  get_target_property(type ${target} TYPE)
  if(CAUSTICA_SANITIZE AND type STREQUAL "STATIC_LIBRARY")
    target_compile_options(${target} PRIVATE -O1)
  endif()
  if(CAUSTICA_FUZZ AND target MATCHES "^caustica_(graph|scene)$")
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()

# Sanitizers are global so that static libraries and the executables linking them agree. Line tables
# (-g1) are all that their stack traces need; full debug information made the build a fifth slower.
if(CAUSTICA_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined -g1)
  add_link_options(-fsanitize=address,undefined)
endif()

# Fuzzing (clang): the libraries the fuzz targets load inputs with (graph and scene files) get
# libFuzzer's coverage instrumentation (caustica_target_defaults), the fuzz targets link the fuzzer
# itself (tests/fuzz). Only those two: in a build that also has the test suite (tools/setup.sh
# test's sanitizer build), the instrumentation made the photon reference's tests twice as slow.
if(CAUSTICA_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "CAUSTICA_FUZZ needs clang (CXX=clang++)")
  endif()
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
