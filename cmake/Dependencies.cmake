# Every dependency comes from a Debian 12 package (see tools/install-deps.sh).
find_package(Threads REQUIRED)            # glslang's config needs Threads first
find_package(Vulkan REQUIRED)
find_package(glslang CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)
find_package(draco CONFIG REQUIRED)          # KHR_draco_mesh_compression
find_package(meshoptimizer CONFIG REQUIRED)  # EXT_meshopt_compression

# Debian's OpenImageIO config lists /usr/include/opencv4, which does not exist without
# libopencv-dev; CMake rejects targets with missing include directories.
foreach(oiio_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${oiio_target})
    get_target_property(oiio_includes ${oiio_target} INTERFACE_INCLUDE_DIRECTORIES)
    if(oiio_includes)
      list(FILTER oiio_includes EXCLUDE REGEX "opencv4")
      set_target_properties(${oiio_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${oiio_includes}")
    endif()
  endif()
endforeach()
