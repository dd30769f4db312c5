# Every dependency comes from a Debian 12 package (see tools/install-deps.sh).
find_package(Threads REQUIRED)            # glslang's config needs Threads first
find_package(Vulkan REQUIRED)
find_package(glslang CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(glm CONFIG REQUIRED)
# Images: EXR through OpenEXR, PNG and the other 8-bit formats through stb (Debian's libstb builds
# stb_image and stb_image_write). OpenImageIO, used before, brought about 270 shared libraries
# whose symbol binding cost every process 0.3 s at start (docs/testing.md).
find_package(OpenEXR CONFIG REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(stb REQUIRED IMPORTED_TARGET stb)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)
find_package(draco CONFIG REQUIRED)          # KHR_draco_mesh_compression
find_package(meshoptimizer CONFIG REQUIRED)  # EXT_meshopt_compression
