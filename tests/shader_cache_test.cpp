// The compiled shaders kept on disk between processes (shader::ShaderDiskCache): a second compiler
// gets what the first compiled without running glslang, byte for byte and with the same
// reflection; an edited include, another build, a damaged entry are misses; old builds' folders go.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "core/paths.h"
#include "shader/shader_disk_cache.h"

using namespace caustica;
using namespace caustica::shader;

namespace {

class ShaderDiskCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::temp_directory_path() /
          ("caustica_shader_cache_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "root" / "lib");
    write("lib/value.glsl", "float value() { return 1.0; }\n");
    write("ok.comp",
          "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"lib/value.glsl\"\n"
          "layout(local_size_x = 8, local_size_y = 4) in;\n"
          "layout(push_constant) uniform Push { float gain; int count; } push;\n"
          "layout(binding = 0) buffer Values { float v[]; };\n"
          "layout(binding = 1, r32f) uniform writeonly image2D target;\n"
          "void main() { v[0] = value() * SCALE * push.gain; imageStore(target, ivec2(0), vec4(push.count)); }\n");
  }
  void TearDown() override { std::filesystem::remove_all(dir); }

  void write(const std::string& name, const std::string& text) const { std::ofstream(dir / "root" / name) << text; }
  // A compiler with an empty memory, as a new process has, over the disk cache of build `build`.
  std::unique_ptr<ShaderCompiler> compiler(const std::string& build = "00112233445566778899") const {
    return std::make_unique<ShaderCompiler>(dir / "root", std::make_unique<ShaderDiskCache>(dir / "cache", build));
  }

  std::filesystem::path dir;
};

TEST_F(ShaderDiskCacheTest, ASecondCompilerReadsWhatTheFirstCompiledWithoutGlslang) {
  auto first = compiler();
  const ReflectedShader compiled = first->compile_reflected("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(first->stats().compiles, 1u);
  EXPECT_EQ(first->stats().disk_hits, 0u);
  auto second = compiler();
  const ReflectedShader read = second->compile_reflected("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(second->stats().compiles, 0u);
  EXPECT_EQ(second->stats().disk_hits, 1u);
  EXPECT_EQ(read.spirv, compiled.spirv);
  EXPECT_EQ(read.reflection, compiled.reflection);
  EXPECT_EQ(read.sources, compiled.sources);
  EXPECT_EQ(read.files, compiled.files);
  // What was reflected, so that the equality above compares something.
  EXPECT_EQ(read.reflection.push_members.size(), 2u);
  EXPECT_EQ(read.reflection.bindings.size(), 2u);
  EXPECT_EQ(read.reflection.local_size[1], 4u);
  // Other defines: another entry.
  second->compile_reflected("ok.comp", {{"SCALE", "3.0"}});
  EXPECT_EQ(second->stats().compiles, 1u);
}

// The library's largest kernel: every kind of binding, a large push block, included files by the
// dozen. Its reflection read back equals the one glslang gave, field by field.
TEST_F(ShaderDiskCacheTest, TheLibrarysPhotonKernelComesBackWithItsWholeReflection) {
  auto fresh = [&] {
    return ShaderCompiler(data_dir() / "shaders", std::make_unique<ShaderDiskCache>(dir / "cache", "aabbccddeeff00112233"));
  };
  ShaderCompiler first = fresh();
  const ReflectedShader compiled = first.compile_reflected("caustics/adaptive_photons.comp");
  ShaderCompiler second = fresh();
  const ReflectedShader read = second.compile_reflected("caustics/adaptive_photons.comp");
  EXPECT_EQ(second.stats().disk_hits, 1u);
  EXPECT_EQ(read.spirv, compiled.spirv);
  EXPECT_EQ(read.reflection, compiled.reflection);
  EXPECT_GT(read.reflection.bindings.size(), 5u);
  EXPECT_GT(read.files.size(), 3u);
}

TEST_F(ShaderDiskCacheTest, AnEditedIncludeCompilesAgain) {
  const auto before = compiler()->compile("ok.comp", {{"SCALE", "2.0"}});
  write("lib/value.glsl", "float value() { return 5.0; }\n");
  auto after = compiler();
  const auto edited = after->compile("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(after->stats().compiles, 1u);
  EXPECT_EQ(after->stats().disk_hits, 0u);
  EXPECT_NE(edited, before);
  // And what it compiled then is what the next one reads.
  auto next = compiler();
  EXPECT_EQ(next->compile("ok.comp", {{"SCALE", "2.0"}}), edited);
  EXPECT_EQ(next->stats().disk_hits, 1u);
}

TEST_F(ShaderDiskCacheTest, AnotherBuildOrADamagedEntryIsAMiss) {
  const auto compiled = compiler()->compile("ok.comp", {{"SCALE", "2.0"}});
  auto other_build = compiler("99887766554433221100");
  other_build->compile("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(other_build->stats().disk_hits, 0u);
  EXPECT_EQ(other_build->stats().compiles, 1u);

  // Every entry of the first build cut to half its length, then one turned into other bytes.
  int entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "cache" / "00112233445566778899")) {
    std::filesystem::resize_file(entry.path(), std::filesystem::file_size(entry.path()) / 2);
    ++entries;
  }
  ASSERT_EQ(entries, 1);
  auto damaged = compiler();
  EXPECT_EQ(damaged->compile("ok.comp", {{"SCALE", "2.0"}}), compiled);
  EXPECT_EQ(damaged->stats().compiles, 1u);
  for (const auto& entry : std::filesystem::directory_iterator(dir / "cache" / "00112233445566778899"))
    std::ofstream(entry.path(), std::ios::binary) << "caustica shader cache 1\n\xff\xff\xff\xff\xff\xff\xff\x7f";
  auto garbage = compiler();
  EXPECT_EQ(garbage->compile("ok.comp", {{"SCALE", "2.0"}}), compiled);
  EXPECT_EQ(garbage->stats().compiles, 1u);
  // Rewritten whole: the next compiler reads it.
  auto next = compiler();
  EXPECT_EQ(next->compile("ok.comp", {{"SCALE", "2.0"}}), compiled);
  EXPECT_EQ(next->stats().disk_hits, 1u);
}

TEST_F(ShaderDiskCacheTest, AFolderThatCannotBeWrittenOnlyMeansCompiling) {
  std::ofstream(dir / "cache") << "a file where the folder would be";
  auto blocked = compiler();
  EXPECT_FALSE(blocked->compile("ok.comp", {{"SCALE", "2.0"}}).empty());
  EXPECT_FALSE(compiler()->compile("ok.comp", {{"SCALE", "2.0"}}).empty());
  // Without a build ID nothing is kept.
  ShaderDiskCache no_build(dir / "elsewhere", "");
  EXPECT_TRUE(no_build.folder().empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "elsewhere"));
}

// A build's folder goes when unused for a week, or when 31 others were used since; a folder in
// use is marked so each time a compiler opens it; what is not a build's folder stays.
TEST_F(ShaderDiskCacheTest, KeepsTheFoldersOfBuildsInUse) {
  const auto now = std::filesystem::file_time_type::clock::now();
  const auto build = [&](int i) { return dir / "cache" / ("00000000000000" + std::string(i < 10 ? "0" : "") + std::to_string(i)); };
  for (int i = 0; i < 40; ++i) {
    std::filesystem::create_directories(build(i));
    std::filesystem::last_write_time(build(i), now - std::chrono::hours(i == 39 ? 24 * 8 : 40 - i));  // 38 the most recent
  }
  std::filesystem::create_directories(dir / "cache" / "notes");
  ShaderDiskCache used(dir / "cache", "0000000000000000");  // build 0's, the oldest but a week: now in use
  EXPECT_GT(std::filesystem::last_write_time(build(0)), now - std::chrono::minutes(1));
  ShaderDiskCache cache(dir / "cache", "ffffffffffffffff");
  EXPECT_EQ(cache.folder(), dir / "cache" / "ffffffffffffffff");
  // Kept: the new one, build 0 (just used) and the 30 most recent of the others (9 to 38).
  EXPECT_TRUE(std::filesystem::exists(build(0)));
  for (int i = 1; i < 9; ++i) EXPECT_FALSE(std::filesystem::exists(build(i))) << "build " << i;
  for (int i = 9; i < 39; ++i) EXPECT_TRUE(std::filesystem::exists(build(i))) << "build " << i;
  EXPECT_FALSE(std::filesystem::exists(build(39))) << "unused for eight days";
  EXPECT_TRUE(std::filesystem::exists(dir / "cache" / "notes"));
}

TEST(ShaderDiskCacheFolder, TheEnvironmentNamesItOrTurnsItOff) {
  auto saved = [](const char* name) { return std::getenv(name) ? std::optional<std::string>(std::getenv(name)) : std::nullopt; };
  const std::optional<std::string> dir = saved("CAUSTICA_SHADER_CACHE_DIR"), xdg = saved("XDG_CACHE_HOME");
  ::setenv("CAUSTICA_SHADER_CACHE_DIR", "off", 1);
  EXPECT_FALSE(ShaderDiskCache::default_folder().has_value());
  ::setenv("CAUSTICA_SHADER_CACHE_DIR", "/some/where", 1);
  EXPECT_EQ(ShaderDiskCache::default_folder(), std::filesystem::path("/some/where"));
  ::unsetenv("CAUSTICA_SHADER_CACHE_DIR");
  ::setenv("XDG_CACHE_HOME", "/x", 1);
  EXPECT_EQ(ShaderDiskCache::default_folder(), std::filesystem::path("/x/caustica/shaders"));
  ::unsetenv("XDG_CACHE_HOME");
  if (dir) ::setenv("CAUSTICA_SHADER_CACHE_DIR", dir->c_str(), 1);
  if (xdg) ::setenv("XDG_CACHE_HOME", xdg->c_str(), 1);
  // This program's own build ID (GCC and clang on Debian link one in): hex, the same each time.
  const std::string id = ShaderDiskCache::build_id();
  EXPECT_GE(id.size(), 16u);
  for (char c : id) EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(c))) << id;
  EXPECT_EQ(ShaderDiskCache::build_id(), id);
}

}  // namespace
