// Runs the caustica binary as a user would: exit codes, messages, files written or not written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace {

struct CliRun {
  int code;
  std::string output;  // stdout and stderr together
};

// Runs `binary args` in `cwd`, its standard error with its output.
CliRun run_binary(const fs::path& binary, const std::string& args, const fs::path& cwd) {
  std::string command = "cd '" + cwd.string() + "' && '" + binary.string() + "' " + args + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

CliRun run(const std::string& args, const fs::path& cwd = fs::temp_directory_path()) {
  return run_binary(CAUSTICA_BIN, args, cwd);
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("caustica_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const fs::path kSource = CAUSTICA_SOURCE_DIR;
const std::string kCoreDemo = "--graph '" + (kSource / "graphs/core_demo.json").string() + "' ";
// Light-space maps of 256 texels for renders that check what a command does, not the maps' detail:
// a fresh 1024^2 map's first touch is most of a one-frame render under the sanitizers.
const std::string kSmallMaps = " --set light_size=256 --set shadow_size=256";

// Runs `caustica validate` on every FOLDER/*.json and checks exit code 1 and the message in its
// .expect file; returns the number of cases.
int check_bad_inputs(const fs::path& folder) {
  int cases = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".json") continue;
    fs::path expect_file = entry.path();
    expect_file.replace_extension(".expect");
    std::string expected = read(expect_file);
    while (!expected.empty() && expected.back() == '\n') expected.pop_back();
    EXPECT_FALSE(expected.empty()) << expect_file;
    CliRun r = run("validate '" + entry.path().filename().string() + "'", folder);
    EXPECT_EQ(r.code, 1) << entry.path().filename() << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << entry.path().filename() << "\nexpected: " << expected << "\ngot: " << r.output;
    ++cases;
  }
  return cases;
}

}  // namespace

TEST(Cli, EveryBadGraphGivesItsMessageAndExitCode1) {
  EXPECT_GE(check_bad_inputs(kSource / "tests/data/bad_graphs"), 30);
}

// Scenes and the meshes they name: malformed JSON, wrong values, missing and broken mesh files,
// and the broken glTF files of Debian's assimp-testmodels.
TEST(Cli, EveryBadSceneGivesItsMessageAndExitCode1) {
  EXPECT_GE(check_bad_inputs(kSource / "tests/data/bad_scenes"), 30);
}

// Bad command lines from tests/data/bad_commands.txt: flags, parameters, missing files, files that
// are not files (a folder, /dev/zero, a named pipe) and files of the wrong type.
TEST(Cli, EveryBadCommandGivesItsMessageAndExitCode) {
  fs::path dir = scratch("commands");
  fs::path pipes = scratch("commands_fifo");
  const fs::path fifo = pipes / "pipe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto substitute = [](std::string text, const std::string& name, const fs::path& value) {
    for (size_t at; (at = text.find(name)) != std::string::npos;) text.replace(at, name.size(), "'" + value.string() + "'");
    return text;
  };
  std::ifstream cases(kSource / "tests/data/bad_commands.txt");
  int count = 0;
  for (std::string line; std::getline(cases, line);) {
    if (line.empty() || line[0] == '#') continue;
    const size_t first = line.find(" | "), second = line.find(" | ", first + 3);
    ASSERT_NE(second, std::string::npos) << "malformed case: " << line;
    const int code = std::stoi(line.substr(0, first));
    std::string args = line.substr(first + 3, second - first - 3);
    const std::string expected = line.substr(second + 3);
    args = substitute(substitute(substitute(args, "$SRC", kSource), "$DATA", kSource / "tests/data"), "$FIFO", fifo);
    CliRun r = run(args + " < /dev/null", dir);
    EXPECT_EQ(r.code, code) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\nexpected: " << expected << "\ngot: " << r.output;
    ++count;
  }
  EXPECT_GE(count, 50);
  EXPECT_TRUE(fs::is_empty(dir)) << "a failed run left files behind";
  fs::remove_all(dir);
  fs::remove_all(pipes);
}

// lavapipe cannot be made to lose its device or run out of memory, so the engine injects those
// results (CAUSTICA_FAULT) where a real device would report them.
TEST(Cli, DeviceLossAndOutOfMemoryExit3AndWriteNothing) {
  fs::path dir = scratch("faults");
  const std::string outputs = "--size 64x48 --frames 2 --stats stats.json --dump lit=lit.exr --out frame.png" + kSmallMaps;
  ::setenv("CAUSTICA_FAULT", "device_lost", 1);
  CliRun lost = run("render " + outputs, dir);
  ::setenv("CAUSTICA_FAULT", "out_of_memory", 1);
  CliRun oom = run("render " + outputs, dir);
  CliRun bench = run("bench photons --grids 64", dir);
  ::unsetenv("CAUSTICA_FAULT");
  EXPECT_EQ(lost.code, 3) << lost.output;
  EXPECT_NE(lost.output.find("device error: vkWaitForFences failed: VK_ERROR_DEVICE_LOST"), std::string::npos) << lost.output;
  EXPECT_EQ(oom.code, 3) << oom.output;
  EXPECT_NE(oom.output.find("failed: VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos) << oom.output;
  EXPECT_EQ(bench.code, 3) << bench.output;
  EXPECT_TRUE(fs::is_empty(dir)) << "a failed run left files behind";
  // The same command without a fault writes all three files.
  CliRun good = run("render " + outputs, dir);
  EXPECT_EQ(good.code, 0) << good.output;
  EXPECT_TRUE(fs::exists(dir / "frame.png") && fs::exists(dir / "stats.json") && fs::exists(dir / "lit.exr"));
  fs::remove_all(dir);
}

TEST(Cli, BundledScenesValidate) {
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    CliRun r = run("validate '" + entry.path().string() + "'");
    EXPECT_EQ(r.code, 0) << r.output;
    ++scenes;
  }
  EXPECT_GE(scenes, 8);
}

// An installed copy runs from anywhere with its own data: `cmake --install` into a prefix, the
// prefix moved to another folder, the binary run from a third one.
TEST(Cli, AnInstalledCopyRunsWhereverItIsMoved) {
  fs::path dir = scratch("install");
  const std::string install = "cmake --install '" CAUSTICA_BUILD_DIR "' --prefix '" + (dir / "first").string() + "' > /dev/null 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << install;
  fs::rename(dir / "first", dir / "moved");
  fs::create_directories(dir / "elsewhere");
  const fs::path bin = dir / "moved" / "bin" / "caustica";
  auto installed = [&](const std::string& args) { return run_binary(bin, args, dir / "elsewhere"); };
  const CliRun help = installed("--help");
  EXPECT_NE(help.output.find("data folder (graphs, shaders, scenes): " + (dir / "moved" / "share" / "caustica").string()),
            std::string::npos)
      << help.output;
  const CliRun render = installed("render --size 32x18 --out x.png");
  EXPECT_EQ(render.code, 0) << render.output;
  EXPECT_TRUE(fs::exists(dir / "elsewhere" / "x.png"));
  fs::remove_all(dir);
}

// As a user types it, `validate graphs/*.json`: every graph ok, the schema beside them skipped.
TEST(Cli, BundledGraphsValidate) {
  std::string files;
  int graphs = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "graphs")) {
    if (entry.path().extension() != ".json") continue;
    files += " '" + entry.path().string() + "'";
    graphs += entry.path().filename() == "schema.json" ? 0 : 1;
  }
  CliRun r = run("validate" + files);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("schema.json: skipped (a JSON Schema"), std::string::npos) << r.output;
  size_t ok = 0;
  for (size_t at = r.output.find(".json: ok"); at != std::string::npos; at = r.output.find(".json: ok", at + 1)) ++ok;
  EXPECT_EQ(ok, static_cast<size_t>(graphs)) << r.output;
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* command : {"", "render ", "trace ", "validate ", "graph ", "graphs ", "scenes ", "devices ", "reference ", "merge ",
                              "bench ", "compare ", "view ", "edit "}) {
    CliRun r = run(std::string(command) + "--help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.output.find("usage:"), std::string::npos) << command;
  }
  // The top-level help names every subcommand of bench and graph.
  const CliRun top = run("--help");
  for (const char* sub : {"'bench refraction'", "'bench photons'", "'bench accuracy'", "'bench stability'", "'bench convergence'",
                          "'graph plan", "'graph dot", "'graph schema'", "'graph set"}) {
    EXPECT_NE(top.output.find(sub), std::string::npos) << sub << " in\n" << top.output;
  }
}

// Compiled shaders are kept between runs (engine/shader/shader_disk_cache.h): the first run writes
// them into the folder CAUSTICA_SHADER_CACHE_DIR names, the second reads them (it rewrites none),
// and both pictures are the one a run that keeps nothing renders.
TEST(Cli, CompiledShadersAreKeptBetweenRunsAndChangeNoPicture) {
  const fs::path dir = scratch("shader_cache");
  const auto render = [&](const std::string& cache, const std::string& out) {
    return run_binary("/usr/bin/env",
                      "CAUSTICA_SHADER_CACHE_DIR=" + cache + " '" + std::string(CAUSTICA_BIN) +
                          "' render --scene sphere_plane --size 32x18" + kSmallMaps + " --out " + out,
                      dir);
  };
  const auto entries = [&] {
    std::map<fs::path, fs::file_time_type> found;
    for (const auto& entry : fs::recursive_directory_iterator(dir / "cache"))
      if (entry.is_regular_file()) found[entry.path()] = entry.last_write_time();
    return found;
  };
  const CliRun off = render("off", "off.png");
  ASSERT_EQ(off.code, 0) << off.output;
  EXPECT_FALSE(fs::exists(dir / "off"));
  const CliRun cold = render("'" + (dir / "cache").string() + "'", "cold.png");
  ASSERT_EQ(cold.code, 0) << cold.output;
  const auto written = entries();
  EXPECT_GT(written.size(), 5u);
  const CliRun warm = render("'" + (dir / "cache").string() + "'", "warm.png");
  ASSERT_EQ(warm.code, 0) << warm.output;
  EXPECT_EQ(entries(), written) << "the second run compiled again";
  EXPECT_EQ(read(dir / "cold.png"), read(dir / "off.png"));
  EXPECT_EQ(read(dir / "warm.png"), read(dir / "off.png"));
  const CliRun help = run_binary("/usr/bin/env", "CAUSTICA_SHADER_CACHE_DIR=/some/where '" + std::string(CAUSTICA_BIN) + "' --help", dir);
  EXPECT_NE(help.output.find("compiled shaders kept in: /some/where (CAUSTICA_SHADER_CACHE_DIR"), std::string::npos) << help.output;
  fs::remove_all(dir);
}

// Every flag a command's --help lists is one its parsing takes, with a value where the help shows
// one: the help and the parsing come from one table. A misspelling of each is refused with it as
// the suggestion.
TEST(Cli, EveryFlagThatHelpListsIsOneTheCommandTakes) {
  fs::path dir = scratch("help_flags");
  // The command (with what it needs before its flags) and the part of --help that lists its flags.
  std::vector<std::pair<std::string, std::string>> commands;
  for (const char* c : {"render", "trace", "validate", "compare", "reference", "merge", "view", "edit"}) {
    const std::string help = run(std::string(c) + " --help", dir).output;
    commands.emplace_back(c, help.substr(help.find("options")));
  }
  const std::string graph_help = run("graph --help", dir).output;
  const size_t set_options = graph_help.find("options of 'graph set'");
  commands.emplace_back("graph set '" + (kSource / "graphs/core_demo.json").string() + "'", graph_help.substr(set_options));
  const std::string bench_help = run("bench --help", dir).output;
  for (const char* b : {"refraction", "compare", "photons", "load", "accuracy", "stability", "convergence", "merge"}) {
    const size_t at = bench_help.find(std::string("\n") + b + " options:\n");
    ASSERT_NE(at, std::string::npos) << b << " options in\n" << bench_help;
    commands.emplace_back(std::string("bench ") + b, bench_help.substr(at + 1, bench_help.find("\n\n", at + 1) - at));
  }
  int flags = 0;
  for (const auto& [command, listing] : commands) {
    std::istringstream lines(listing);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("  --", 0) != 0) continue;
      const size_t end = line.find(' ', 2);
      const std::string flag = line.substr(2, end - 2);
      const bool takes_value = line.size() > end + 1 && line[end + 1] != ' ';  // "--size WxH   ...", not "--json   ..."
      const CliRun misspelt = run(command + " " + flag + "q", dir);
      EXPECT_EQ(misspelt.code, 2) << command << " " << flag << "q\n" << misspelt.output;
      EXPECT_NE(misspelt.output.find("unknown option '" + flag + "q' (did you mean '" + flag + "'?)"), std::string::npos)
          << command << " " << flag << "q\n"
          << misspelt.output;
      // Taken as the help says: a value it needs, or a switch given twice.
      const CliRun taken = run(command + " " + flag + (takes_value ? "" : " " + flag), dir);
      const std::string expected = flag + (takes_value ? " needs a value" : " is given twice: give it once");
      EXPECT_EQ(taken.code, 2) << command << " " << flag << "\n" << taken.output;
      EXPECT_NE(taken.output.find(expected), std::string::npos)
          << command << " " << flag << "\nexpected: " << expected << "\ngot: " << taken.output;
      ++flags;
    }
  }
  EXPECT_GE(flags, 150);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// A headless render is at rest, as the viewer once nothing moves: the graph's while_still values
// (caustics_progressive: distance=ray_query, exact photons), unless --set sets the parameter or
// --moving asks for the declared values; a device without ray queries traces them with the compute
// tracer, and one asked for ray queries that lacks them falls back to the declared values with a
// note, rather than failing.
TEST(Cli, HeadlessRendersAtRestUnlessMovingOrSet) {
  fs::path dir = scratch("at_rest");
  const std::string base = "render --graph caustics_progressive --scene sphere_plane --size 64x36" + kSmallMaps + " --out x.png --stats ";
  const auto exact_photons = [&](const std::string& stats) {
    return nlohmann::json::parse(read(dir / stats))["counters"].value("photons.exact", 0.0);
  };
  const CliRun rest = run(base + "rest.json", dir);
  ASSERT_EQ(rest.code, 0) << rest.output;
  EXPECT_GT(exact_photons("rest.json"), 0.0);
  const CliRun moving = run(base + "moving.json --moving", dir);
  ASSERT_EQ(moving.code, 0) << moving.output;
  EXPECT_EQ(exact_photons("moving.json"), 0.0);
  const CliRun set = run(base + "set.json --set distance=search", dir);
  ASSERT_EQ(set.code, 0) << set.output;
  EXPECT_EQ(exact_photons("set.json"), 0.0);
  // Without ray queries the values at rest trace with the compute tracer; where ray queries are
  // asked for and missing, the declared values stand in, with a note.
  ::setenv("CAUSTICA_NO_RAY_QUERY", "1", 1);
  const CliRun compute = run(base + "compute.json", dir);
  const CliRun refused = run(base + "refused.json --tracer ray_query", dir);
  ::unsetenv("CAUSTICA_NO_RAY_QUERY");
  ASSERT_EQ(compute.code, 0) << compute.output;
  EXPECT_GT(exact_photons("compute.json"), 0.0);
  EXPECT_EQ(compute.output.find("not those at rest"), std::string::npos) << compute.output;
  ASSERT_EQ(refused.code, 0) << refused.output;
  EXPECT_NE(refused.output.find("the values as declared, not those at rest (distance=ray_query"), std::string::npos) << refused.output;
  EXPECT_EQ(exact_photons("refused.json"), 0.0);
  fs::remove_all(dir);
}

// --scene takes a model file as a scene of its own: render, reference and validate open it alike,
// and --no-stage leaves the floor out (so the pictures differ).
TEST(Cli, ModelFilesOpenAsScenes) {
  fs::path dir = scratch("model_scene");
  const std::string model = (kSource / "tests/data/gltf/cube_camera_spot.gltf").string();
  CliRun staged = run("render --validate --size 96x54 --scene " + model + " --out staged.png", dir);
  ASSERT_EQ(staged.code, 0) << staged.output;
  CliRun bare = run("render --validate --size 96x54 --no-stage --scene " + model + " --out bare.png", dir);
  ASSERT_EQ(bare.code, 0) << bare.output;
  EXPECT_NE(run("compare staged.png bare.png --max-l1 0.01", dir).code, 0) << "the stage made no difference";
  CliRun reference = run("reference --size 96x54 --scene " + model + " --out reference.png", dir);
  EXPECT_EQ(reference.code, 0) << reference.output;
  // A quantized copy of the model (KHR_mesh_quantization) renders the same picture.
  CliRun quantized =
      run("render --size 96x54 --scene " + (kSource / "tests/data/gltf/cube_quantized.gltf").string() + " --out quantized.png", dir);
  ASSERT_EQ(quantized.code, 0) << quantized.output;
  EXPECT_EQ(run("compare staged.png quantized.png --max-l1 0", dir).code, 0) << run("compare staged.png quantized.png", dir).output;
  CliRun validated = run("validate " + model, dir);
  EXPECT_EQ(validated.code, 0) << validated.output;
  EXPECT_NE(validated.output.find("cube_camera_spot.gltf: ok"), std::string::npos) << validated.output;
  fs::remove_all(dir);
}

// A model's picture does not depend on where it stands or how large it is: the stage, camera and
// light are fitted to its bounds, and the depth tests hold at any scale. A cube 80 units across at
// z = -1000 (as tests/data/gltf/dragon.glb stands) lights like the unit cube at the origin, with a
// 4096^2 shadow map; before the biases followed the shadow map's texels and depth steps and the
// camera's near plane the model's size, its floor was streaked: relative L1 0.0043 (0.0021 with the
// camera's near plane the default 0.05), now 0.0003.
TEST(Cli, AModelLightsAlikeAtAnyPlaceAndScale) {
  fs::path dir = scratch("far_model");
  auto write_cube = [&](const std::string& name, float scale, float z) {
    std::ofstream obj(dir / name);
    for (int i = 0; i < 8; ++i)
      obj << "v " << (i & 4 ? scale : -scale) << " " << (i & 2 ? scale : -scale) << " " << (i & 1 ? scale : -scale) + z << "\n";
    for (const char* face : {"1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"}) {
      int a, b, c, d;
      std::sscanf(face, "%d %d %d %d", &a, &b, &c, &d);
      obj << "f " << a << " " << b << " " << c << "\nf " << a << " " << c << " " << d << "\n";
    }
  };
  write_cube("near.obj", 1.0f, 0.0f);
  write_cube("far.obj", 80.0f, -1000.0f);
  for (const char* name : {"near", "far"}) {
    CliRun r = run(std::string("render --validate --size 320x180 --set shadow_size=4096 --scene ") + name + ".obj --dump lit=" + name +
                       ".exr --out " + name + ".png",
                   dir);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  CliRun same = run("compare far.exr near.exr --blur 0 --max-l1 0.001", dir);
  EXPECT_EQ(same.code, 0) << same.output;
  fs::remove_all(dir);
}

// Losslessly compressed copies of the dragon (Draco without quantization, meshopt without
// KHR_mesh_quantization; tests/data/gltf/make_compressed.sh) render the uncompressed glTF's picture.
TEST(Cli, CompressedModelsRenderAsTheirOriginal) {
  fs::path dir = scratch("compressed");
  const std::string common = "render --validate --size 96x54 --scene ";
  CliRun original = run(common + (kSource / "tests/data/gltf/dragon.glb").string() + " --out original.png", dir);
  ASSERT_EQ(original.code, 0) << original.output;
  for (const char* file : {"dragon_draco_lossless.glb", "dragon_meshopt_lossless.glb"}) {
    CliRun compressed = run(common + (kSource / "tests/data/gltf" / file).string() + " --out compressed.png", dir);
    ASSERT_EQ(compressed.code, 0) << compressed.output;
    EXPECT_EQ(run("compare original.png compressed.png --max-l1 0", dir).code, 0)
        << file << ": " << run("compare original.png compressed.png", dir).output;
  }
  fs::remove_all(dir);
}

// A point light throws its caustic through a view fitted to its refractors: over a glass ball the
// caustic graph plans and runs its per-light passes without a word; inside the ball no frustum
// holds it, and it throws through the six faces of a cube about it, each a caustic view with its
// own instances (graph plan names them under the light; its shadow, a cube map, is one pass). A
// graph whose caustic passes are made once draws the first face alone, and render, validate
// --scene and graph plan say so. A spot or directional light says nothing.
TEST(Cli, APointLightAmongItsRefractorsThrowsThroughCubeFaces) {
  fs::path dir = scratch("point_light");
  const std::string graph = (kSource / "graphs/caustics_adaptive.json").string();
  const std::string over = (kSource / "tests/data/point_light.json").string(),
                    inside = (kSource / "tests/data/point_light_inside.json").string();
  CliRun lit = run("render --size 96x54 --scene " + over + " --out p.png", dir);
  ASSERT_EQ(lit.code, 0) << lit.output;
  EXPECT_EQ(lit.output.find("warning:"), std::string::npos) << lit.output;
  CliRun lit_plan = run("graph plan " + graph + " --scene " + over, dir);
  ASSERT_EQ(lit_plan.code, 0) << lit_plan.output;
  EXPECT_NE(lit_plan.output.find("\"caustics#0\""), std::string::npos) << lit_plan.output;
  EXPECT_NE(lit_plan.output.find("\"warnings\": []"), std::string::npos) << lit_plan.output;
  // Which light got which passes, and its caustic view fitted to the ball (not the floor).
  const nlohmann::json lit_lights = nlohmann::json::parse(lit_plan.output)["lights"];
  ASSERT_EQ(lit_lights.size(), 1u) << lit_plan.output;
  EXPECT_EQ(lit_lights[0]["passes"].get<std::set<std::string>>(),
            (std::set<std::string>{"shadow#0", "receivers#0", "light_refractors#0", "caustics#0"}))
      << lit_plan.output;
  EXPECT_EQ(lit_lights[0]["caustic_view"]["fitted_to_refractors"], true) << lit_plan.output;

  CliRun point = run("render --size 96x54 --scene " + inside + " --out i.png", dir);
  ASSERT_EQ(point.code, 0) << point.output;
  EXPECT_EQ(point.output.find("warning:"), std::string::npos) << point.output;
  CliRun plan = run("graph plan " + graph + " --scene " + inside, dir);
  ASSERT_EQ(plan.code, 0) << plan.output;
  EXPECT_NE(plan.output.find("\"warnings\": []"), std::string::npos) << plan.output;
  const nlohmann::json inside_light = nlohmann::json::parse(plan.output)["lights"].at(0);
  EXPECT_EQ(inside_light["caustic_view"]["cube_faces"], nlohmann::json::array({"+x", "-x", "+y", "-y", "+z", "-z"})) << plan.output;
  std::set<std::string> passes{"shadow#0"};
  for (int view = 0; view < 6; ++view) {
    for (const char* pass : {"receivers", "light_refractors", "caustics"}) passes.insert(std::string(pass) + "#" + std::to_string(view));
  }
  EXPECT_EQ(inside_light["passes"].get<std::set<std::string>>(), passes) << plan.output;
  CliRun spot = run("render --size 96x54 --scene " + (kSource / "scenes/sphere_plane.json").string() + " --out s.png", dir);
  ASSERT_EQ(spot.code, 0) << spot.output;
  EXPECT_EQ(spot.output.find("warning:"), std::string::npos) << spot.output;
  // A graph made for one light draws one face of six; validate --scene says so without a device.
  const std::string one_light = (kSource / "graphs/examples/caustic_filter.json").string();
  CliRun validated = run("validate " + one_light + " --scene " + inside, dir);
  EXPECT_EQ(validated.code, 0) << validated.output;
  EXPECT_NE(validated.output.find("caustic_filter.json: warning: light 0 is a point light among its refractors, which throws its "
                                  "caustics through 6 cube faces"),
            std::string::npos)
      << validated.output;
  CliRun directional = run("validate " + graph + " --scene " + (kSource / "scenes/sphere_sun.json").string(), dir);
  EXPECT_EQ(directional.code, 0) << directional.output;
  EXPECT_EQ(directional.output.find("warning:"), std::string::npos) << directional.output;
  fs::remove_all(dir);
}

// Bundled graphs and scenes are found from any folder: by the path they have in the data folder, by
// their file name, or by their bare name; a file of that name where one runs comes first, and a
// name found nowhere is refused naming the bundled file it stood for.
TEST(Cli, BundledGraphsAndScenesAreFoundFromAnyFolder) {
  fs::path dir = scratch("bundled_names");
  const std::string small = " --size 32x18 --out ";
  EXPECT_EQ(run("render --graph caustics_regular --scene sphere_plane --set grid=64" + small + "names.png", dir).code, 0);
  EXPECT_EQ(run("render --graph graphs/core_demo.json" + small + "relative.png", dir).code, 0);
  EXPECT_EQ(run("render --graph caustics_regular.json --scene stability/close_light --set grid=64" + small + "files.png", dir).code, 0);
  EXPECT_TRUE(fs::exists(dir / "names.png") && fs::exists(dir / "relative.png") && fs::exists(dir / "files.png"));
  const CliRun validate = run("validate caustics_regular sphere_plane", dir);
  EXPECT_EQ(validate.code, 0) << validate.output;
  EXPECT_NE(validate.output.find((kSource / "graphs" / "caustics_regular.json").string() + ": ok"), std::string::npos) << validate.output;
  EXPECT_NE(validate.output.find((kSource / "scenes" / "sphere_plane.json").string() + ": ok"), std::string::npos) << validate.output;
  EXPECT_EQ(run("graph plan core_demo", dir).code, 0);
  // A file of the given name where one runs is that file, not the bundled one.
  std::ofstream(dir / "core_demo.json") << "{ \"broken\": ";
  const CliRun local = run("validate core_demo.json", dir);
  EXPECT_EQ(local.code, 1) << local.output;
  EXPECT_NE(local.output.find("core_demo.json:1:"), std::string::npos) << local.output;
  const CliRun missing = run("render --graph no_such_graph" + small + "missing.png", dir);
  EXPECT_EQ(missing.code, 1) << missing.output;
  EXPECT_NE(missing.output.find((kSource / "graphs" / "no_such_graph.json").string() + ": cannot open"), std::string::npos)
      << missing.output;
  EXPECT_FALSE(fs::exists(dir / "missing.png"));
  fs::remove_all(dir);
}

TEST(Cli, DefaultRenderWritesCausticaPng) {
  fs::path dir = scratch("default");
  CliRun r = run("", dir);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_GT(fs::file_size(dir / "caustica.png"), 1000u);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().filename());
  EXPECT_EQ(files.size(), 1u) << "temporary files left behind";
  fs::remove_all(dir);
}

TEST(Cli, RenderStatsDumpAndTraceWithValidation) {
  fs::path dir = scratch("render");
  CliRun r = run("render " + kCoreDemo +
                     "--validate --size 160x90 --frames 3 --set blur_radius=1 --stats stats.json --dump hdr=hdr.exr --out frame.exr",
                 dir);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
  auto stats = nlohmann::json::parse(read(dir / "stats.json"));
  ASSERT_EQ(stats["passes"].size(), 4u);
  for (const auto& p : stats["passes"]) {
    EXPECT_TRUE(p.contains("name") && p.contains("gpu_ms") && p.contains("cpu_ms"));
  }
  EXPECT_GT(stats["frame"]["gpu_ms"].get<double>(), 0);
  EXPECT_TRUE(stats["counters"].contains("tonemap.bright_pixels"));
  EXPECT_GT(stats["memory"]["transient_bytes_unaliased"].get<uint64_t>(), 0u);
  EXPECT_GT(fs::file_size(dir / "hdr.exr"), 1000u);
  EXPECT_GT(fs::file_size(dir / "frame.exr"), 1000u);
  // An EXR holds linear values: --out F.exr writes the tonemap's input, not its 8-bit picture, and
  // the summary names it and every --dump file.
  EXPECT_NE(r.output.find("-> frame.exr (linear: 'blurred', the graph's linear_output), hdr -> hdr.exr"), std::string::npos) << r.output;
  // Both in one run: the picture and the linear result.
  CliRun linear =
      run("render " + kCoreDemo + "--size 160x90 --set blur_radius=1 --dump blurred=blurred.exr --out frame.exr --out frame.png", dir);
  ASSERT_EQ(linear.code, 0) << linear.output;
  EXPECT_EQ(run("compare frame.exr blurred.exr --max-l1 0", dir).code, 0);
  CliRun display = run("render " + kCoreDemo + "--size 160x90 --set blur_radius=1 --out display.png", dir);
  ASSERT_EQ(display.code, 0) << display.output;
  EXPECT_EQ(run("compare frame.png display.png --max-l1 0", dir).code, 0) << "the picture written beside the EXR differs";
  EXPECT_NE(run("compare frame.exr frame.png --max-l1 0.01", dir).code, 0) << "the EXR holds the display values";
  // The graph says which resource is its linear result: another one declared, that one is written;
  // none declared, the tonemap's input.
  for (const auto& [declared, expected] : {std::pair<std::string, std::string>{"hdr", "hdr"}, {"", "blurred"}}) {
    nlohmann::json graph = nlohmann::json::parse(std::ifstream(kSource / "graphs/core_demo.json"));
    graph.erase("$schema");
    if (declared.empty()) {
      graph.erase("linear_output");
    } else {
      graph["linear_output"] = declared;
    }
    std::ofstream(dir / "declared.json") << graph.dump(2);
    CliRun written =
        run("render --graph declared.json --size 160x90 --set blur_radius=1 --dump " + expected + "=expected.exr --out linear.exr", dir);
    ASSERT_EQ(written.code, 0) << written.output;
    EXPECT_EQ(run("compare linear.exr expected.exr --max-l1 0", dir).code, 0) << "linear_output '" << declared << "'";
  }

  CliRun t = run("trace " + kCoreDemo + "--validate --size 640x360 --frames 4 --out trace.json", dir);
  ASSERT_EQ(t.code, 0) << t.output;
  auto trace = nlohmann::json::parse(read(dir / "trace.json"));
  std::set<std::string> gpu_passes;
  double frame_start = 0, frame_end = 0;
  std::vector<std::pair<double, double>> pass_spans;
  for (const auto& ev : trace["traceEvents"]) {
    if (ev["ph"] != "X" || ev["tid"] != 1 || ev["args"]["frame"] != 3) continue;
    const double start = ev["ts"].get<double>(), end = start + ev["dur"].get<double>();
    if (ev["name"] == "frame 3") {
      frame_start = start;
      frame_end = end;
    } else {
      gpu_passes.insert(ev["name"].get<std::string>());
      pass_spans.emplace_back(start, end);
    }
  }
  EXPECT_EQ(gpu_passes, (std::set<std::string>{"pattern", "blur_x", "blur_y", "tonemap"}));
  // The GPU track holds the passes one after the other inside their frame (timestamps, not their
  // lengths, which a loaded CPU device stretches: an NVIDIA H200 spent 60.9 of 67.9 us in passes,
  // lavapipe beside other work as little as 78%). Rounded to the trace's 0.001 us.
  std::sort(pass_spans.begin(), pass_spans.end());
  for (size_t i = 0; i < pass_spans.size(); ++i) {
    EXPECT_GE(pass_spans[i].first, frame_start - 0.001);
    EXPECT_LE(pass_spans[i].second, frame_end + 0.001);
    if (i > 0) {
      EXPECT_GE(pass_spans[i].first, pass_spans[i - 1].second - 0.001) << "passes overlap on the GPU track";
    }
  }
  EXPECT_EQ(trace["otherData"]["graph"], "core_demo");
  fs::remove_all(dir);
}

// Either half of lighting's caustic pair renders (the editor connects one port at a time), with a
// warning that names what it means: without the receivers' depth the caustic map is applied with no
// receiver test. Validation layers on.
// render --orbit runs the viewer's scripted orbit without a window: the light's passes run once and
// are reused while the camera turns, and the last frame is the picture of a plain render with the
// camera turned as far (here the scene file's camera turned by hand, 3 x 10 degrees about y). Three
// float turns and one in double put the camera an ulp or so apart, which the refraction through the
// bunny moves by a texel in a few places (relative L1 8e-4); the unturned picture is 0.76 away.
TEST(Cli, AnOrbitReusesTheLightsPassesAndEndsAtThePictureOfItsLastCamera) {
  fs::path dir = scratch("orbit");
  CliRun orbit = run("render --validate --size 160x90 --frames 4 --orbit 10 --stats stats.json --out orbit.exr" + kSmallMaps, dir);
  ASSERT_EQ(orbit.code, 0) << orbit.output;
  const auto stats = nlohmann::json::parse(read(dir / "stats.json"));
  ASSERT_EQ(stats["frames_timed"].get<int>(), 3);
  std::map<std::string, int> frames_run;
  for (const auto& p : stats["passes"]) frames_run[p["name"].get<std::string>()] = p["frames_run"].get<int>();
  for (const char* light_pass : {"shadow#0", "receivers#0", "light_refractors#0", "caustics#0"})
    EXPECT_EQ(frames_run.at(light_pass), 0) << light_pass;
  for (const char* camera_pass : {"gbuffer", "lighting", "refraction", "tonemap"}) EXPECT_EQ(frames_run.at(camera_pass), 3) << camera_pass;
  const auto& frame = stats["frame"];
  EXPECT_LE(frame["wall_ms"].get<double>(), frame["wall_ms_p95"].get<double>());
  EXPECT_LE(frame["wall_ms_p95"].get<double>(), frame["wall_ms_p99"].get<double>());

  nlohmann::json scene = nlohmann::json::parse(std::ifstream(kSource / "scenes/glass_bunny.json"));
  const double turn = 30.0 * 3.14159265358979 / 180.0;
  auto& position = scene["camera"]["position"];
  const double x = position[0].get<double>() - scene["camera"]["target"][0].get<double>();
  const double z = position[2].get<double>() - scene["camera"]["target"][2].get<double>();
  position[0] = scene["camera"]["target"][0].get<double>() + std::cos(turn) * x + std::sin(turn) * z;
  position[2] = scene["camera"]["target"][2].get<double>() - std::sin(turn) * x + std::cos(turn) * z;
  std::ofstream(dir / "turned.json") << scene.dump(2);
  CliRun turned = run("render --size 160x90 --scene turned.json --out turned.exr" + kSmallMaps, dir);
  ASSERT_EQ(turned.code, 0) << turned.output;
  CliRun unturned = run("render --size 160x90 --out unturned.exr" + kSmallMaps, dir);
  ASSERT_EQ(unturned.code, 0) << unturned.output;
  EXPECT_EQ(run("compare orbit.exr turned.exr --blur 0 --max-l1 0.003", dir).code, 0);
  EXPECT_NE(run("compare orbit.exr unturned.exr --blur 0 --max-l1 1e-3", dir).code, 0) << "the camera did not turn";
}

TEST(Cli, ACausticMapWithoutItsReceiverDepthRendersWithAWarning) {
  fs::path dir = scratch("half_pair");
  nlohmann::json graph = nlohmann::json::parse(std::ifstream(kSource / "graphs/caustics_regular.json"));
  graph.erase("$schema");
  for (auto& pass : graph["passes"]) {
    if (pass["name"] == "lighting") pass["inputs"].erase("caustic_depth");
  }
  std::ofstream(dir / "g.json") << graph.dump(2);
  CliRun r = run("render --graph g.json --scene '" + (kSource / "scenes/sphere_plane.json").string() +
                     "' --size 64x36 --set grid=64 --set caustic_size=64 --set light_size=64 --validate --out g.png",
                 dir);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("'caustics' is bound without 'caustic_depth': the caustic map is applied without its receiver test"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(dir / "g.png"));
  fs::remove_all(dir);
}

// caustica graphs / scenes, from a folder outside the source tree: every bundled file once, by the
// name --graph and --scene take there, with the first sentence of its description.
TEST(Cli, BundledGraphsAndScenesAreListedByTheNamesTheFlagsTake) {
  fs::path dir = scratch("listing");
  for (const auto& [command, folder] : {std::pair<std::string, std::string>{"graphs", "graphs"}, {"scenes", "scenes"}}) {
    CliRun r = run(command, dir);
    ASSERT_EQ(r.code, 0) << r.output;
    size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(kSource / folder)) {
      if (!entry.is_regular_file() || entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
      ++files;
      const std::string name = fs::relative(entry.path(), kSource / folder).replace_extension().generic_string();
      EXPECT_NE(r.output.find("\n  " + name + " "), std::string::npos) << name << " is not listed:\n" << r.output;
    }
    EXPECT_EQ(static_cast<size_t>(std::count(r.output.begin(), r.output.end(), '\n')), files + 1) << r.output;
  }
  const CliRun graphs = run("graphs", dir);
  const size_t line = graphs.output.find("\n  caustics_regular ");
  ASSERT_NE(line, std::string::npos);
  EXPECT_NE(graphs.output.substr(line, graphs.output.find('\n', line + 1) - line)
                .find("Regular caustic maps (Wyman and Nichols 2009's baseline)"),
            std::string::npos)
      << graphs.output;
  // Each listed name is what the flags take from here.
  EXPECT_EQ(run("validate caustics_regular stability/close_light", dir).code, 0);
  EXPECT_EQ(run("graphs extra", dir).code, 2);
  fs::remove_all(dir);
}

// graph params: the graph's parameters (what --set reaches) with type, value, range and the
// viewer's values, then each pass's, bound to a graph parameter or its own, and which follow the frame.
TEST(Cli, GraphParamsListsWhatAGraphTakes) {
  fs::path dir = scratch("params");
  CliRun r = run("graph params caustics_progressive", dir);
  ASSERT_EQ(r.code, 0) << r.output;
  auto line_of = [&](const std::string& start) {
    const size_t at = r.output.find(start);
    return at == std::string::npos ? std::string("(missing: " + start + ")") : r.output.substr(at, r.output.find('\n', at) - at);
  };
  EXPECT_NE(r.output.find("graph parameters of caustics_progressive (render, view, bench: --set NAME=VALUE"), std::string::npos)
      << r.output;
  const std::string distance = line_of("  distance ");
  EXPECT_NE(distance.find("choice  dv_dn"), std::string::npos) << distance;
  EXPECT_NE(distance.find("dv|dv_dn|search|ray_query|hybrid|material"), std::string::npos) << distance;
  EXPECT_NE(distance.find("[while still: ray_query]"), std::string::npos) << distance;
  EXPECT_NE(line_of("  grid ").find("int     256             16 to 16384"), std::string::npos) << line_of("  grid ");
  EXPECT_NE(r.output.find("  caustics (caustic_map)\n"), std::string::npos) << r.output;
  const std::string pass_grid = line_of("    grid ");
  EXPECT_NE(pass_grid.find("$grid"), std::string::npos) << pass_grid;
  EXPECT_NE(pass_grid.find("[per frame]"), std::string::npos) << pass_grid;
  EXPECT_NE(line_of("    seed ").find("1 (default)"), std::string::npos) << line_of("    seed ");
  EXPECT_EQ(run("graph params", dir).code, 2);
  CliRun missing = run("graph params no_such_graph", dir);
  EXPECT_EQ(missing.code, 1) << missing.output;
  fs::remove_all(dir);
}

// The photon grid is an integer in every pass type and graph: --set grid=1024 gives the adaptive
// traversal the number 1024 (tests/data/bad_commands.txt: one that is not a power of two is refused
// with the nearest ones), and a file of old, where it was a choice of strings, still reads and renders the same.
TEST(Cli, ThePhotonGridIsAnIntegerAndOldFilesStillRead) {
  fs::path dir = scratch("grid");
  auto grid_of = [](const CliRun& plan) {
    const auto parsed = nlohmann::json::parse(plan.output);
    for (const auto& pass : parsed["passes"]) {
      if (pass["type"] == "adaptive_caustic_map") return pass["params"]["grid"];
    }
    return nlohmann::json();
  };
  const CliRun plan = run("graph plan caustics_adaptive --set grid=1024", dir);
  ASSERT_EQ(plan.code, 0) << plan.output;
  EXPECT_EQ(grid_of(plan), 1024) << plan.output;
  EXPECT_TRUE(nlohmann::json::parse(plan.output)["warnings"].empty()) << plan.output;
  const CliRun params = run("graph params caustics_hierarchical", dir);
  const std::string grid_line = params.output.substr(params.output.find("  grid "), 80);
  EXPECT_NE(grid_line.find("int     2048            64 to 65536, powers of two"), std::string::npos) << grid_line;

  // The bundled graph as it was written before: the grid a choice of strings.
  std::string old = read(kSource / "graphs/caustics_adaptive.json");
  const std::string declared =
      "\"type\": \"int\",\n      \"default\": 2048,\n      \"while_moving\": 512,\n      \"min\": 64,\n"
      "      \"max\": 65536,\n      \"power_of_two\": true,";
  const size_t at = old.find(declared);
  ASSERT_NE(at, std::string::npos) << "the grid's declaration in graphs/caustics_adaptive.json changed";
  old.replace(
      at, declared.size(),
      "\"type\": \"choice\", \"default\": \"2048\", \"while_moving\": \"512\",\n"
      "      \"choices\": [\"64\", \"128\", \"256\", \"512\", \"1024\", \"2048\", \"4096\", \"8192\", \"16384\", \"32768\", \"65536\"],");
  std::ofstream(dir / "old.json") << old;
  const CliRun old_plan = run("graph plan old.json --set grid=1024", dir);
  ASSERT_EQ(old_plan.code, 0) << old_plan.output;
  EXPECT_EQ(grid_of(old_plan), 1024) << old_plan.output;
  const CliRun validated = run("validate old.json", dir);
  EXPECT_EQ(validated.code, 0) << validated.output;
  EXPECT_NE(validated.output.find("warning: old.json:"), std::string::npos) << validated.output;
  EXPECT_NE(validated.output.find("graph parameter 'grid' is a choice of strings, and parameter 'grid' of pass 'caustics#0' "
                                  "(adaptive_caustic_map) takes an integer, so it reads \"2048\" as 2048; declare 'grid' as "
                                  "\"type\": \"int\" with numbers and \"power_of_two\": true"),
            std::string::npos)
      << validated.output;
  // The same photons: the counters are exact, the flux a sum of float atomics in any order.
  const std::string small = " --scene sphere_plane --size 64x36 --set grid=256 --set caustic_size=64 --out x.png --stats ";
  ASSERT_EQ(run("render --graph caustics_adaptive" + small + "new_stats.json", dir).code, 0);
  const CliRun old_render = run("render --graph old.json" + small + "old_stats.json", dir);
  ASSERT_EQ(old_render.code, 0) << old_render.output;
  EXPECT_NE(old_render.output.find("caustica: warning: old.json:"), std::string::npos) << old_render.output;
  const auto counters = nlohmann::json::parse(read(dir / "new_stats.json"))["counters"];
  const auto old_counters = nlohmann::json::parse(read(dir / "old_stats.json"))["counters"];
  EXPECT_GT(counters["photons.processed"].get<double>(), 0.0);
  for (const char* exact : {"photons.processed", "photons.splatted", "photons.converged"})
    EXPECT_EQ(old_counters[exact], counters[exact]) << exact;
  EXPECT_NEAR(old_counters["caustic.flux"].get<double>(), counters["caustic.flux"].get<double>(),
              1e-4 * counters["caustic.flux"].get<double>());
  fs::remove_all(dir);
}

TEST(Cli, GraphPlanAndDot) {
  CliRun plan = run("graph plan '" + (kSource / "graphs/core_demo.json").string() + "' --size 640x360");
  ASSERT_EQ(plan.code, 0) << plan.output;
  auto j = nlohmann::json::parse(plan.output);
  EXPECT_EQ(j["order"], nlohmann::json({"pattern", "blur_x", "blur_y", "tonemap"}));
  EXPECT_EQ(j["culled"], nlohmann::json({"unused_preview"}));
  EXPECT_LT(j["memory"]["transient_bytes_aliased"].get<uint64_t>(), j["memory"]["transient_bytes_unaliased"].get<uint64_t>());
  CliRun dot = run("graph dot '" + (kSource / "graphs/core_demo.json").string() + "'");
  ASSERT_EQ(dot.code, 0);
  EXPECT_EQ(dot.output.rfind("digraph", 0), 0u);
  EXPECT_NE(dot.output.find("(culled)"), std::string::npos);
  // Line breaks in labels are Graphviz's \n escape, not a backslash that Graphviz prints.
  EXPECT_NE(dot.output.find("unused_preview\\n(culled)"), std::string::npos) << dot.output;
  EXPECT_EQ(dot.output.find("\\\\n"), std::string::npos) << dot.output;
  // Piped into Graphviz as the README does (tools/install-deps.sh installs it): the culled pass's
  // label is two lines of text, with no backslash left in it.
  CliRun svg = run("graph dot '" + (kSource / "graphs/core_demo.json").string() + "' | dot -Tsvg");
  EXPECT_EQ(svg.code, 0) << svg.output;
  EXPECT_NE(svg.output.find(">unused_preview</text>"), std::string::npos) << svg.output;
  EXPECT_NE(svg.output.find(">(culled)</text>"), std::string::npos) << svg.output;
  EXPECT_EQ(svg.output.find("\\n"), std::string::npos) << svg.output;
}

// Every bundled graph's placement comes within a tenth of the bound its lifetimes set (the most
// transient bytes alive at once over the plan's order, which the compiler chose for the least such
// peak: compiler_test), and the aliasing halves the default graph's transient memory or comes
// within 1% of its bound where the bound itself is above half.
TEST(Cli, BundledGraphsAliasCloseToTheirLifetimeBound) {
  for (const auto& entry : fs::directory_iterator(kSource / "graphs")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
    const CliRun plan = run("graph plan '" + entry.path().string() + "' --size 1280x720");
    ASSERT_EQ(plan.code, 0) << entry.path() << plan.output;
    const auto j = nlohmann::json::parse(plan.output);
    uint64_t bound = 0;
    for (size_t at = 0; at < j["order"].size(); ++at) {
      uint64_t live = 0;
      for (const auto& r : j["resources"]) {
        if (r["used"] && r["transient"] && r["lifetime"][0] <= at && at <= r["lifetime"][1]) live += r["bytes"].get<uint64_t>();
      }
      bound = std::max(bound, live);
    }
    const auto aliased = j["memory"]["transient_bytes_aliased"].get<double>();
    const auto unaliased = j["memory"]["transient_bytes_unaliased"].get<double>();
    EXPECT_EQ(j["memory"]["transient_bytes_lifetime_bound"].get<uint64_t>(), bound) << entry.path();
    EXPECT_GE(aliased, static_cast<double>(bound)) << entry.path();
    EXPECT_LE(aliased, 1.1 * static_cast<double>(bound)) << entry.path();
    std::printf("%-36s aliased/unaliased %.3f, lifetime bound %.3f\n", entry.path().filename().c_str(), aliased / unaliased,
                static_cast<double>(bound) / unaliased);
    if (entry.path().filename() == "caustics_adaptive.json") {
      EXPECT_LE(aliased, 0.5 * unaliased) << "the default graph";
    }
  }
}

// graph set (and the viewer's Save) changes the parameter values and nothing else in the file.
TEST(Cli, GraphSetWritesOnlyTheValues) {
  fs::path dir = scratch("graph_set");
  const std::string original = read(kSource / "graphs/caustics_adaptive.json");
  std::ofstream(dir / "g.json") << original;
  CliRun set = run("graph set g.json grid=4096 fresnel=false exposure=1.25 --out edited.json", dir);
  ASSERT_EQ(set.code, 0) << set.output;
  std::string expected = original;
  auto replace_default = [&](const std::string& parameter, const std::string& from, const std::string& to) {
    const size_t at = expected.find("\"" + parameter + "\": {");
    ASSERT_NE(at, std::string::npos) << parameter;
    const size_t value = expected.find("\"default\": " + from, at);
    ASSERT_NE(value, std::string::npos) << parameter;
    expected.replace(value, std::string("\"default\": ").size() + from.size(), "\"default\": " + to);
  };
  replace_default("grid", "2048", "4096");
  replace_default("fresnel", "true", "false");
  const size_t exposure = expected.find("\"exposure\": {");
  const size_t exposure_default = expected.find("\"default\": ", exposure) + std::string("\"default\": ").size();
  expected.replace(exposure_default, expected.find_first_of(",\n}", exposure_default) - exposure_default, "1.25");
  EXPECT_EQ(read(dir / "edited.json"), expected);
  EXPECT_EQ(read(dir / "g.json"), original) << "--out leaves the source alone";
  EXPECT_EQ(run("validate edited.json", dir).code, 0);
  // In place, and a refused value leaves the file as it was.
  ASSERT_EQ(run("graph set g.json grid=512", dir).code, 0);
  EXPECT_NE(read(dir / "g.json").find("\"default\": 512,"), std::string::npos);
  const std::string before = read(dir / "g.json");
  EXPECT_EQ(run("graph set g.json exposure=-5", dir).code, 1);
  EXPECT_EQ(read(dir / "g.json"), before);
  fs::remove_all(dir);
}

TEST(Cli, CheckedInSchemaMatchesThePassRegistry) {
  CliRun schema = run("graph schema");
  ASSERT_EQ(schema.code, 0);
  EXPECT_EQ(nlohmann::json::parse(schema.output), nlohmann::json::parse(read(kSource / "graphs/schema.json")))
      << "graphs/schema.json is stale: regenerate it with 'caustica graph schema > graphs/schema.json'";
}

TEST(Cli, ReferenceAndBenchmarksRun) {
  fs::path dir = scratch("bench");
  const std::string sphere = "'" + (kSource / "scenes/sphere_plane.json").string() + "'";
  CliRun ref = run("reference --scene " + sphere + " --size 64X36 --out ref.exr", dir);
  ASSERT_EQ(ref.code, 0) << ref.output;
  EXPECT_GT(fs::file_size(dir / "ref.exr"), 1000u);

  CliRun photons = run("bench photons --scene " + sphere + " --grids 64,128 --frames 1 --out photons", dir);
  ASSERT_EQ(photons.code, 0) << photons.output;
  EXPECT_NE(photons.output.find("| 128^2 |"), std::string::npos) << photons.output;
  const std::string csv = read(dir / "photons" / "photons.csv");
  EXPECT_EQ(csv.rfind("grid,method,processed,gpu_ms\n", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 6);  // header, two grids x six methods (max error twice)
  EXPECT_NE(csv.find("128,adaptive_max_error_same_texel,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("128,regular,16384,"), std::string::npos) << csv;

  CliRun refraction = run("bench refraction --sphere-detail 16 --size 64x36 --frames 2 --csv refraction.csv", dir);
  ASSERT_EQ(refraction.code, 0) << refraction.output;
  EXPECT_NE(read(dir / "refraction.csv").find("sphere, detail 16,224,"), std::string::npos);
  // No scene given: the bundled ball lens and bunny; one timed frame is enough to ask for. Piped, the
  // progress comes as whole lines, never carriage returns that run together.
  CliRun bundled = run("bench refraction --size 64x36 --frames 1 --csv bundled.csv", dir);
  ASSERT_EQ(bundled.code, 0) << bundled.output;
  const std::string rows = read(dir / "bundled.csv");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 3) << rows;  // header, ball lens, bunny
  EXPECT_EQ(bundled.output.find('\r'), std::string::npos) << bundled.output;
  EXPECT_NE(bundled.output.find(": frames 3/3"), std::string::npos) << bundled.output;
  fs::remove_all(dir);
}

// reference --picture: every light's photons, shared by flux (the shares printed), then the picture
// lit by their maps; the same as each light's map traced alone with its share and the picture
// traced from those maps (--caustics I=MAP), bit for bit: the way a cluster makes it.
TEST(Cli, TheReferencePictureIsEveryLightsMapThenThePictureTheyLight) {
  fs::path dir = scratch("picture");
  const std::string scene = " --scene '" + (kSource / "scenes/three_lights.json").string() + "' --map-size 32";
  const CliRun picture = run("reference" + scene + " --photons 30000 --size 48x27 --picture picture.exr", dir);
  ASSERT_EQ(picture.code, 0) << picture.output;
  std::string maps;
  uint64_t shared = 0;
  for (int light = 0; light < 3; ++light) {
    const std::string said = "--light " + std::to_string(light) + " --photons ";
    const size_t at = picture.output.find(said);
    ASSERT_NE(at, std::string::npos) << picture.output;
    const uint64_t share = std::stoull(picture.output.substr(at + said.size()));
    EXPECT_GT(share, 0u);
    shared += share;
    const std::string map = "map" + std::to_string(light) + ".exr";
    const CliRun alone =
        run("reference" + scene + " --light " + std::to_string(light) + " --photons " + std::to_string(share) + " --out " + map, dir);
    ASSERT_EQ(alone.code, 0) << alone.output;
    maps += " --caustics " + std::to_string(light) + "=" + map;
  }
  EXPECT_EQ(shared, 30000u);
  const CliRun lit = run("reference" + scene + " --size 48x27" + maps + " --out lit.exr", dir);
  ASSERT_EQ(lit.code, 0) << lit.output;
  EXPECT_EQ(run("compare picture.exr lit.exr --blur 0 --max-l1 0", dir).code, 0);
  const CliRun unlit = run("reference" + scene + " --size 48x27 --out unlit.exr", dir);
  ASSERT_EQ(unlit.code, 0) << unlit.output;
  EXPECT_NE(run("compare picture.exr unlit.exr --blur 0 --max-l1 1e-3", dir).code, 0) << "the maps lit nothing";
  fs::remove_all(dir);
}

// The photon reference, compare on it, and the speed-accuracy benchmark with its chart.
TEST(Cli, PhotonReferenceCompareAndAccuracyBenchmark) {
  fs::path dir = scratch("accuracy");
  const std::string sphere = "'" + (kSource / "scenes/sphere_plane.json").string() + "'";
  CliRun ref = run("reference --scene " + sphere + " --photons 2e5 --map-size 64 --camera camera.exr --size 64x36 --out a.exr", dir);
  ASSERT_EQ(ref.code, 0) << ref.output;
  EXPECT_NE(ref.output.find("photons 200000 in"), std::string::npos) << ref.output;
  EXPECT_TRUE(fs::exists(dir / "camera.exr"));
  ASSERT_EQ(run("reference --scene " + sphere + " --photons 2e5 --map-size 64 --seed 7 --out b.exr", dir).code, 0);
  // The reference picture lit with that map (caustics_test checks its projection against the engine's).
  const CliRun picture = run("reference --scene " + sphere + " --caustics a.exr --exposure 1.5 --size 64x36 --out picture.png", dir);
  EXPECT_EQ(picture.code, 0) << picture.output;
  EXPECT_TRUE(fs::exists(dir / "picture.png"));

  CliRun same = run("compare a.exr a.exr --json", dir);
  ASSERT_EQ(same.code, 0) << same.output;
  const auto metrics = nlohmann::json::parse(same.output);
  EXPECT_EQ(metrics["relative_l1"].get<double>(), 0.0);
  EXPECT_EQ(metrics["energy_ratio"].get<double>(), 1.0);
  // Two seeds: the same caustic up to photon noise, which --max-l1 0 refuses and --max-l1 1 accepts.
  CliRun seeds = run("compare a.exr b.exr", dir);
  ASSERT_EQ(seeds.code, 0) << seeds.output;
  EXPECT_NE(seeds.output.find("energy_ratio"), std::string::npos);
  EXPECT_EQ(run("compare a.exr b.exr --max-l1 0", dir).code, 1);
  EXPECT_EQ(run("compare a.exr b.exr --max-l1 1", dir).code, 0);

  CliRun bench =
      run("bench accuracy --scenes sphere_plane --graphs caustics_adaptive:converge_test=within_texel,refraction_deferred --grids 64,128 "
          "--reference-photons 1e5 "
          "--caustic-size 64 --size 64x36 --frames 1 --out \"it's acc\"",  // the chart's command line quotes the folder
          dir);
  ASSERT_EQ(bench.code, 0) << bench.output;
  const fs::path acc = dir / "it's acc";
  const std::string csv = read(acc / "results.csv");
  EXPECT_EQ(csv.rfind("scene,kind,method,grid,photons_processed,method_ms,frame_ms,relative_l1,energy_ratio,shape_l1,psnr,nonfinite\n", 0),
            0u)
      << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 + 3);  // header, two grids, three image-space distances
  EXPECT_NE(csv.find("sphere_plane,caustics,caustics_adaptive converge_test=within_texel,128,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("sphere_plane,refraction,refraction_deferred dv_dn,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("sphere_plane,refraction,refraction_deferred search,0,"), std::string::npos) << csv;
  EXPECT_GT(fs::file_size(acc / "speed_accuracy.png"), 10000u);
  EXPECT_NE(read(acc / "README.md").find("| sphere_plane | caustics_adaptive converge_test=within_texel | 128^2 |"), std::string::npos);
  fs::remove_all(dir);
}

// caustica reference ARGS in `dir`, outside a scheduler but for the variables of `env` ("NAME=VALUE").
CliRun reference_run(const std::string& args, const std::string& env, const fs::path& dir) {
  return run_binary("/usr/bin/env", "-u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX " + env + " '" + CAUSTICA_BIN + "' reference " + args,
                    dir);
}

// Each `caustica merge SHARDS --out refused.exr` in `dir` exits 1 naming MESSAGE and writes nothing.
void expect_merge_refusals(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& refusals) {
  for (const auto& [shards, message] : refusals) {
    const CliRun refused = run("merge " + shards + " --out refused.exr", dir);
    EXPECT_EQ(refused.code, 1) << shards << "\n" << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << "expected: " << message << "\ngot: " << refused.output;
    EXPECT_FALSE(fs::exists(dir / "refused.exr"));
  }
}

// A user graph by its path on the chart, its rows beside the built-ins': caustic_map_user's photon
// pass is the built-in caustic_map's as a user pass, so its caustic row is the built-in's, metric
// for metric (tests/user_pass_test.cpp checks the maps themselves).
TEST(Cli, BenchAccuracyTakesAUserGraphByPath) {
  const fs::path dir = scratch("user_accuracy");
  const CliRun bench = run("bench accuracy --scenes sphere_plane --graphs caustics_regular,'" +
                               (kSource / "graphs/examples/caustic_map_user.json").string() +
                               "' --grids 64 --reference-photons 1e5 --caustic-size 64 --size 64x36 --frames 1 --out acc",
                           dir);
  ASSERT_EQ(bench.code, 0) << bench.output;
  const std::string csv = read(dir / "acc/results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2) << csv;  // header, one caustic row each
  // The metrics after the method's and the frame's times.
  auto metrics = [&](const std::string& method) {
    const size_t row = csv.find("sphere_plane,caustics," + method + ",64,4096,");
    if (row == std::string::npos) return "(no row for " + method + ")";
    std::string line = csv.substr(row, csv.find('\n', row) - row);
    for (int field = 0; field < 7; ++field) line.erase(0, line.find(',') + 1);
    return line;
  };
  EXPECT_EQ(metrics("caustic_map_user"), metrics("caustics_regular")) << csv;
  fs::remove_all(dir);
}

// bench compare times caustic methods side by side in one process, frames interleaved: example (a)'s
// user passes (its clear and photon pass write 'caustics') against the built-in caustic_map they
// replace, each graph charged with its own caustic passes; a graph without any is refused.
TEST(Cli, BenchCompareTimesEachGraphsCausticPassesInOneRun) {
  const fs::path dir = scratch("compare");
  const std::string user = (kSource / "graphs/examples/caustic_map_user.json").string();
  const CliRun bench = run("bench compare --graphs caustics_regular,'" + user + "' --size 64x36 --frames 2 --set grid=64 --csv c.csv", dir);
  ASSERT_EQ(bench.code, 0) << bench.output;
  EXPECT_NE(bench.output.find("| caustics_regular | caustics | "), std::string::npos) << bench.output;
  EXPECT_NE(bench.output.find("| " + user + " | caustic_clear, caustics | "), std::string::npos) << bench.output;
  std::istringstream csv(read(dir / "c.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "graph,caustic_ms,frame_ms,caustic_ratio,frame_ratio");
  std::vector<std::vector<double>> rows;
  while (std::getline(csv, line)) {
    std::vector<double> values;
    std::istringstream fields(line.substr(line.find(',') + 1));
    for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
    rows.push_back(values);
  }
  ASSERT_EQ(rows.size(), 2u) << read(dir / "c.csv");
  for (const auto& row : rows) {
    EXPECT_GT(row[0], 0.0) << "a caustic time of nothing";
    EXPECT_GT(row[1], row[0]) << "the frame takes less than its caustic passes";
  }
  EXPECT_EQ(rows[0][2], 1.0);
  EXPECT_NEAR(rows[1][2], rows[1][0] / rows[0][0], 2e-3 * rows[1][2]) << "the ratio is not the second's time over the first's";
  fs::remove_all(dir);
}

// The photon reference as shards, as a cluster runs it (docs/cluster.md): four shards, two of
// them indexed by the scheduler's variables, merge into the map of one process bit for bit; shards
// that do not make one map are refused with exit 1, naming what is wrong, and nothing is written.
TEST(Cli, ShardedReferenceMergesToTheWholeMapAndRefusesStrayShards) {
  const fs::path dir = scratch("shards");
  const std::string sphere = "--scene '" + (kSource / "scenes/sphere_plane.json").string() + "' --map-size 32 ";
  auto reference = [&](const std::string& args, const std::string& env = "") { return reference_run(args, env, dir); };
  ASSERT_EQ(reference(sphere + "--photons 1e5 --out whole.exr").code, 0);
  for (int i : {0, 1})
    ASSERT_EQ(reference(sphere + "--photons 1e5 --shard " + std::to_string(i) + "/4 --out s" + std::to_string(i) + ".exr").code, 0);
  const CliRun slurm = reference(sphere + "--photons 1e5 --shard auto/4 --out s3.exr", "SLURM_ARRAY_TASK_ID=3");
  ASSERT_EQ(slurm.code, 0) << slurm.output;
  EXPECT_NE(slurm.output.find("shard 3/4: photons 75000 to 99999 of 100000"), std::string::npos) << slurm.output;
  ASSERT_EQ(reference(sphere + "--photons 1e5 --shard auto/4 --out s2.exr", "JOB_COMPLETION_INDEX=2").code, 0);
  const CliRun merged = run("merge s3.exr s1.exr s0.exr s2.exr --out merged.exr", dir);
  ASSERT_EQ(merged.code, 0) << merged.output;
  EXPECT_NE(merged.output.find("merged 4 shards: photons 100000, seed 1, scene sphere_plane"), std::string::npos) << merged.output;
  const CliRun same = run("compare merged.exr whole.exr --json", dir);
  ASSERT_EQ(same.code, 0) << same.output;
  EXPECT_EQ(nlohmann::json::parse(same.output)["max_error"].get<double>(), 0.0);

  const CliRun no_index = reference(sphere + "--photons 1e5 --shard auto/4 --out auto.exr");
  EXPECT_EQ(no_index.code, 2);
  EXPECT_NE(no_index.output.find("neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX"), std::string::npos)
      << no_index.output;
  const CliRun bad_index = reference(sphere + "--photons 1e5 --shard auto/4 --out auto.exr", "SLURM_ARRAY_TASK_ID=4");
  EXPECT_EQ(bad_index.code, 2);
  EXPECT_NE(bad_index.output.find("(the index that SLURM_ARRAY_TASK_ID gives, '4', is not a whole number from 0 to 3)"), std::string::npos)
      << bad_index.output;

  ASSERT_EQ(reference(sphere + "--photons 1e5 --shard 1/3 --out third.exr").code, 0);
  ASSERT_EQ(reference(sphere + "--photons 1e5 --seed 2 --shard 3/4 --out seed2.exr").code, 0);
  ASSERT_EQ(reference(sphere + "--photons 2e5 --shard 3/4 --out count.exr").code, 0);
  ASSERT_EQ(
      reference("--scene '" + (kSource / "scenes/sphere_sun.json").string() + "' --map-size 32 --photons 1e5 --shard 3/4 --out sun.exr")
          .code,
      0);
  fs::copy_file(dir / "s2.exr", dir / "copy.exr");
  const std::vector<std::pair<std::string, std::string>> refusals = {
      {"s0.exr s1.exr s3.exr", "photons 50000 to 74999 are missing: shard 2 of 4"},
      {"s0.exr s1.exr s2.exr s3.exr third.exr", "third.exr (photons 33333 to 66665) overlaps s1.exr (photons 25000 to 49999)"},
      {"s0.exr s1.exr s2.exr s3.exr copy.exr", "copy.exr and s2.exr are the same shard (photons 50000 to 74999)"},
      {"s0.exr s1.exr s2.exr seed2.exr", "seed2.exr: seed 2, where s0.exr has 1"},
      {"s0.exr s1.exr s2.exr count.exr", "count.exr: photon count 200000, where s0.exr has 100000"},
      {"s0.exr s1.exr s2.exr sun.exr", "sun.exr: scene sphere_sun (identity "},
  };
  expect_merge_refusals(dir, refusals);
  const CliRun as_image = run("compare s0.exr whole.exr", dir);
  EXPECT_EQ(as_image.code, 1);
  EXPECT_NE(as_image.output.find("s0.exr: cannot read image: it has no R or Y channel (a photon shard: caustica merge makes the map)"),
            std::string::npos)
      << as_image.output;

  // A shard killed while tracing leaves nothing, not even its temporary file.
  const fs::path killed = scratch("killed_shard");
  const CliRun kill = run_binary(
      "/usr/bin/timeout",
      "-s KILL 0.5 '" + std::string(CAUSTICA_BIN) + "' reference " + sphere + "--photons 1e10 --shard 0/2 --out killed.exr", killed);
  EXPECT_EQ(kill.code, 137) << kill.output;
  EXPECT_TRUE(fs::is_empty(killed));
  fs::remove_all(killed);
  fs::remove_all(dir);
}

// The ray-traced camera reference as shards of rows (docs/cluster.md): three shards, two of them
// indexed by the scheduler's variables, merge into the very file one process writes; shards that
// do not make one image are refused with exit 1, naming what is wrong, and nothing is written.
TEST(Cli, ShardedCameraReferenceMergesToTheWholeImageAndRefusesStrayShards) {
  const fs::path dir = scratch("camera_shards");
  const std::string sphere = "--scene '" + (kSource / "scenes/sphere_plane.json").string() + "' --size 32x18 ";
  auto reference = [&](const std::string& args, const std::string& env = "") { return reference_run(args, env, dir); };
  ASSERT_EQ(reference(sphere + "--out whole.exr").code, 0);
  ASSERT_EQ(reference(sphere + "--shard 0/3 --out s0.exr").code, 0);
  const CliRun slurm = reference(sphere + "--shard auto/3 --out s1.exr", "SLURM_ARRAY_TASK_ID=1");
  ASSERT_EQ(slurm.code, 0) << slurm.output;
  EXPECT_NE(slurm.output.find("shard 1/3: rows 6 to 11 of 32x18"), std::string::npos) << slurm.output;
  ASSERT_EQ(reference(sphere + "--shard auto/3 --out s2.exr", "JOB_COMPLETION_INDEX=2").code, 0);
  const CliRun merged = run("merge s2.exr s0.exr s1.exr --out merged.exr", dir);
  ASSERT_EQ(merged.code, 0) << merged.output;
  EXPECT_NE(merged.output.find("merged 3 shards: image 32x18, seed 1, scene sphere_plane"), std::string::npos) << merged.output;
  EXPECT_EQ(read(dir / "merged.exr"), read(dir / "whole.exr"));  // the same file, byte for byte

  ASSERT_EQ(reference(sphere + "--seed 2 --shard 2/3 --out seed2.exr").code, 0);
  ASSERT_EQ(reference("--scene '" + (kSource / "scenes/sphere_sun.json").string() + "' --size 32x18 --shard 2/3 --out sun.exr").code, 0);
  ASSERT_EQ(reference(sphere + "--photons 1000 --map-size 8 --shard 2/3 --out photons.exr").code, 0);
  const std::vector<std::pair<std::string, std::string>> refusals = {
      {"s0.exr s1.exr", "rows 12 to 17 are missing: shard 2 of 3"},
      {"s0.exr s1.exr s2.exr s2.exr", "s2.exr is given twice"},
      {"s0.exr s1.exr seed2.exr", "seed2.exr: seed 2, where s0.exr has 1"},
      {"s0.exr s1.exr sun.exr", "sun.exr: scene sphere_sun (identity "},
      {"s0.exr s1.exr photons.exr", "photons.exr: not a camera shard (a photon shard; merge the kinds apart)"},
  };
  expect_merge_refusals(dir, refusals);
  const CliRun as_image = run("compare s0.exr whole.exr", dir);
  EXPECT_EQ(as_image.code, 1);
  EXPECT_NE(as_image.output.find("s0.exr: cannot read image: it is a camera shard"), std::string::npos) << as_image.output;
  const std::vector<std::pair<std::string, std::string>> usage = {
      {sphere + "--shard 0/19 --out s.exr", "--shard 0/19: more shards than the 18 rows of the image"},
      {sphere + "--shard 0/3 --out s.png", "s.png: a shard is an EXR of the image's rows: --out must end in .exr"},
      {sphere + "--shard 0/3 --exposure 2 --out s.exr", "--exposure goes without --shard"},
  };
  for (const auto& [args, message] : usage) {
    const CliRun refused = reference(args);
    EXPECT_EQ(refused.code, 2) << args << "\n" << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << "expected: " << message << "\ngot: " << refused.output;
  }
  EXPECT_FALSE(fs::exists(dir / "s.exr"));
  fs::remove_all(dir);
}

// A CSV without the columns named in `drop` (the timings, which no two runs share).
std::string without_columns(const std::string& csv, const std::set<std::string>& drop) {
  std::istringstream lines(csv);
  std::string header, kept;
  std::getline(lines, header);
  std::vector<bool> keep;
  for (std::istringstream cells(header); std::getline(cells, header, ',');) keep.push_back(!drop.count(header));
  lines.seekg(0);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream cells(line);
    size_t column = 0;
    for (std::string cell; std::getline(cells, cell, ','); ++column) kept += column < keep.size() && keep[column] ? cell + "," : "";
    kept += "\n";
  }
  return kept;
}

// bench accuracy by cell, as a job array runs it (docs/cluster.md, "Sweeps by cell"): the cells
// listed alike every time, each run alone (one indexed by Slurm's variable) against one reference
// cache, and their merge the results.csv, table and chart of one process, equal but for the
// timings. Cells that do not make one sweep are refused with exit 1 and nothing is written.
TEST(Cli, AccuracySweepByCellMergesToTheOneProcessResults) {
  const fs::path dir = scratch("cells");
  const std::string sweep =
      "bench accuracy --scenes sphere_plane --graphs caustics_adaptive,refraction_deferred --grids 64,128 --reference-photons 1e5 "
      "--caustic-size 64 --size 64x36 ";
  const CliRun list = run(sweep + "--frames 1 --list-cells", dir);
  ASSERT_EQ(list.code, 0) << list.output;
  EXPECT_EQ(list.output,
            "0 sphere_plane caustics_adaptive grid=64\n1 sphere_plane caustics_adaptive grid=128\n"
            "2 sphere_plane refraction_deferred distance=dv,dv_dn,search\n");
  EXPECT_EQ(run(sweep + "--frames 1 --list-cells --out unused", dir).output, list.output);
  EXPECT_FALSE(fs::exists(dir / "unused"));

  for (const char* cell : {"0", "2"}) {
    const CliRun r = run(sweep + "--frames 1 --cell " + cell + " --out cells --reference-cache cache", dir);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const CliRun slurm = run_binary(
      "/usr/bin/env",
      "SLURM_ARRAY_TASK_ID=1 '" + std::string(CAUSTICA_BIN) + "' " + sweep + "--frames 1 --cell auto --out cells --reference-cache cache",
      dir);
  ASSERT_EQ(slurm.code, 0) << slurm.output;
  EXPECT_NE(slurm.output.find("bench accuracy: cell 1 of 3 -> cells/cell_1.csv"), std::string::npos) << slurm.output;
  // The two caustic cells share one reference, traced by the first as one shard in a folder named by its key.
  ASSERT_EQ(std::distance(fs::directory_iterator(dir / "cache"), fs::directory_iterator()), 1);
  const fs::path key = fs::directory_iterator(dir / "cache")->path();
  EXPECT_NE(key.filename().string().find("-p100000-m64-s1"), std::string::npos) << key;
  EXPECT_TRUE(fs::exists(key / "shard_0.exr"));

  const CliRun merged = run("bench merge cells --out merged", dir);
  ASSERT_EQ(merged.code, 0) << merged.output;
  const CliRun whole = run(sweep + "--frames 1 --out whole", dir);
  ASSERT_EQ(whole.code, 0) << whole.output;
  const std::string csv = read(dir / "merged/results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 + 3) << csv;
  EXPECT_EQ(without_columns(csv, {"method_ms", "frame_ms"}), without_columns(read(dir / "whole/results.csv"), {"method_ms", "frame_ms"}));
  EXPECT_NE(read(dir / "merged/README.md").find("| sphere_plane | caustics_adaptive | 128^2 |"), std::string::npos);
  EXPECT_GT(fs::file_size(dir / "merged/speed_accuracy.png"), 10000u);

  fs::create_directories(dir / "gap");
  fs::copy_file(dir / "cells/cell_0.csv", dir / "gap/cell_0.csv");
  fs::copy_file(dir / "cells/cell_2.csv", dir / "gap/cell_2.csv");
  fs::create_directories(dir / "again");
  fs::copy_file(dir / "cells/cell_2.csv", dir / "again/cell_2.csv");
  ASSERT_EQ(run(sweep + "--frames 2 --cell 1 --out other --reference-cache cache", dir).code, 0);
  const std::vector<std::pair<std::string, std::string>> refusals = {
      {"gap", "cells 1 of 3 are missing: run them (--cell K) or resubmit them (tools/slurm/submit.sh --bench ... --resubmit 1)"},
      {"cells again", "again/cell_2.csv and cells/cell_2.csv are both cell 2"},
      {"gap other", "other/cell_1.csv: a cell of another sweep (bench accuracy --scenes sphere_plane"},
  };
  for (const auto& [folders, message] : refusals) {
    const CliRun refused = run("bench merge " + folders + " --out refused", dir);
    EXPECT_EQ(refused.code, 1) << folders << "\n" << refused.output;
    EXPECT_NE(refused.output.find(message), std::string::npos) << "expected: " << message << "\ngot: " << refused.output;
    EXPECT_FALSE(fs::exists(dir / "refused"));
  }
  fs::remove_all(dir);
}

// bench stability by cell: a case's methods run one a process (Kubernetes' index for one of them)
// and merge into the stability.csv and table of one process; --frames 0 leaves no timings, so the
// files are equal whole.
TEST(Cli, StabilitySweepByCellMergesToTheOneProcessResults) {
  const fs::path dir = scratch("stability_cells");
  const std::string sweep = "bench stability --cases no_refractor --grid 64 --caustic-size 32 --frames 0 --reference-photons 1e4 ";
  const CliRun list = run(sweep + "--list-cells", dir);
  ASSERT_EQ(list.code, 0) << list.output;
  EXPECT_EQ(std::count(list.output.begin(), list.output.end(), '\n'), 9) << list.output;
  EXPECT_EQ(list.output.rfind("0 no_refractor caustics_regular grid=64\n1 no_refractor caustics_hierarchical grid=64\n", 0), 0u)
      << list.output;
  EXPECT_NE(list.output.find("\n5 no_refractor caustics_adaptive:coverage_seeding=false grid=64\n"), std::string::npos) << list.output;
  const CliRun indexed = run_binary(
      "/usr/bin/env",
      "JOB_COMPLETION_INDEX=5 '" + std::string(CAUSTICA_BIN) + "' " + sweep + "--cell auto --out cells --reference-cache cache", dir);
  ASSERT_EQ(indexed.code, 0) << indexed.output;
  const CliRun partial = run("bench merge cells --out merged", dir);
  EXPECT_EQ(partial.code, 1);
  EXPECT_NE(partial.output.find("cells 0,1,2,3,4,6,7,8 of 9 are missing"), std::string::npos) << partial.output;
  for (int k : {0, 1, 2, 3, 4, 6, 7, 8}) {
    const CliRun r = run(sweep + "--cell " + std::to_string(k) + " --out cells --reference-cache cache", dir);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const CliRun merged = run("bench merge cells --out merged", dir);
  ASSERT_EQ(merged.code, 0) << merged.output;
  ASSERT_EQ(run(sweep + "--out whole", dir).code, 0);
  EXPECT_EQ(read(dir / "merged/stability.csv"), read(dir / "whole/stability.csv"));
  const std::string table = read(dir / "merged/README.md");
  EXPECT_EQ(table, read(dir / "whole/README.md"));
  EXPECT_NE(table.find("| no refractor | adaptive hybrid unseeded (the paper) |"), std::string::npos) << table;
  fs::remove_all(dir);
}

// bench convergence: each method's mean over the frames against the photon reference. On the ball
// lens the ray-query mean converges toward the reference (its error after 16 frames well below its
// first frame's, and below the d_V/d_N mean's, which keeps that estimate's bias); without ray queries
// that method is skipped with a note and the others run.
TEST(Cli, ConvergenceBenchmarkFollowsEachMeanTowardTheReference) {
  fs::path dir = scratch("convergence");
  const std::string options =
      "bench convergence --scene sphere_plane --grid 64 --caustic-size 64 --size 64x36 --reference-photons 2e6 --frames 16 --methods ";
  // A folder where bench accuracy wrote its results (one row of each kind here): its chart is drawn
  // again with the convergence panel beside.
  fs::create_directories(dir / "conv");
  std::ofstream(dir / "conv" / "results.csv")
      << "scene,kind,method,grid,photons_processed,method_ms,frame_ms,relative_l1,energy_ratio,shape_l1,psnr,nonfinite\n"
         "sphere_plane,caustics,caustics_regular,64,4096,1.5,9.0,0.3,0.8,0.2,30,0\n"
         "sphere_plane,refraction,refraction_deferred dv_dn,0,0,2.0,9.0,0.1,nan,nan,nan,0\n";
  const CliRun bench = run(options + "dv_dn,ray_query --out conv", dir);
  ASSERT_EQ(bench.code, 0) << bench.output;
  EXPECT_GT(fs::file_size(dir / "conv" / "speed_accuracy.png"), 10000u);
  const std::string csv = read(dir / "conv" / "convergence.csv");
  ASSERT_EQ(csv.rfind("scene,method,frame,seconds,frame_ms,relative_l1,energy_ratio,shape_l1\n", 0), 0u) << csv;
  std::map<std::string, std::vector<std::pair<int, double>>> errors;  // method: (frame, relative L1)
  std::map<std::string, double> seconds;
  std::istringstream lines(csv.substr(csv.find('\n') + 1));
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 8u) << line;
    EXPECT_EQ(cells[0], "sphere_plane");
    EXPECT_GE(std::stod(cells[3]), seconds[cells[1]]) << "the clock ran backwards: " << line;
    seconds[cells[1]] = std::stod(cells[3]);
    errors[cells[1]].emplace_back(std::stoi(cells[2]), std::stod(cells[5]));
  }
  // Compared after frames 1 to 8, then four a doubling: 10, 12, 14, 16.
  const std::vector<int> compared{1, 2, 3, 4, 5, 6, 7, 8, 10, 12, 14, 16};
  for (const char* method : {"dv_dn", "ray_query"}) {
    std::vector<int> frames;
    for (const auto& [frame, error] : errors[method]) frames.push_back(frame);
    EXPECT_EQ(frames, compared) << method;
  }
  const double exact_first = errors["ray_query"].front().second, exact_last = errors["ray_query"].back().second;
  const double estimate_last = errors["dv_dn"].back().second;
  std::printf("ray_query relative L1 %.4f after one frame, %.4f after 16; dv_dn %.4f after 16\n", exact_first, exact_last, estimate_last);
  EXPECT_LT(exact_last, 0.6 * exact_first);
  EXPECT_LT(exact_last, estimate_last);
  EXPECT_GT(fs::file_size(dir / "conv" / "convergence.png"), 10000u);
  EXPECT_NE(read(dir / "conv" / "convergence.md").find("| ray_query | "), std::string::npos);

  // Ray queries asked for (--tracer ray_query) where the device has none: that method is skipped, named.
  ::setenv("CAUSTICA_NO_RAY_QUERY", "1", 1);
  const CliRun masked =
      run(options.substr(0, options.find("--frames")) + "--frames 2 --methods dv_dn,ray_query --tracer ray_query --out masked", dir);
  ::unsetenv("CAUSTICA_NO_RAY_QUERY");
  ASSERT_EQ(masked.code, 0) << masked.output;
  EXPECT_NE(masked.output.find("ray_query: skipped on"), std::string::npos) << masked.output;
  const std::string masked_csv = read(dir / "masked" / "convergence.csv");
  EXPECT_NE(masked_csv.find("sphere_plane,dv_dn,2,"), std::string::npos) << masked_csv;
  EXPECT_EQ(masked_csv.find("ray_query"), std::string::npos) << masked_csv;
  fs::remove_all(dir);
}

// bench accuracy draws its chart last, after what can be an hour on lavapipe: an interpreter without
// matplotlib (CAUSTICA_PYTHON chooses it) stops it before any work, exit 3, the package named,
// nothing written.
TEST(Cli, AccuracyBenchmarkWithoutMatplotlibStopsBeforeItStarts) {
  fs::path dir = scratch("no_matplotlib");
  ::setenv("CAUSTICA_PYTHON", "/bin/false", 1);
  const CliRun bench =
      run("bench accuracy --scenes sphere_plane --graphs caustics_adaptive --grids 64 --reference-photons 1e5 --out acc", dir);
  ::unsetenv("CAUSTICA_PYTHON");
  EXPECT_EQ(bench.code, 3) << bench.output;
  EXPECT_NE(bench.output.find("python3-matplotlib"), std::string::npos) << bench.output;
  EXPECT_EQ(bench.output.find("reference photons"), std::string::npos) << bench.output;
  EXPECT_FALSE(fs::exists(dir / "acc"));
  fs::remove_all(dir);
}

// A device without ray queries (masked with CAUSTICA_NO_RAY_QUERY) traces exact paths with the
// compute tracer: the exact photon graph and the hybrid camera graph validate and render, and say
// which tracer ran. Asking for ray queries there (--tracer ray_query) is refused, in validate and
// before rendering: exit 1, the pass, the missing extension and the tracer to use named, nothing
// written; a tracer that does not exist is a usage error.
TEST(Cli, WithoutRayQueriesExactGraphsTraceWithTheComputeTracer) {
  fs::path dir = scratch("no_ray_query");
  const std::string raytraced = "'" + (kSource / "graphs/caustics_raytraced.json").string() + "'";
  const std::string sphere = " --scene '" + (kSource / "scenes/sphere_plane.json").string() + "' --set shadow_size=256";
  const std::string small = " --set light_size=256 --set grid=128 --size 64x36";
  ::setenv("CAUSTICA_NO_RAY_QUERY", "1", 1);
  const CliRun validate = run("validate " + raytraced, dir);
  const CliRun render = run("render --graph " + raytraced + sphere + small + " --out x.png --stats x.json", dir);
  const std::string hybrid = "'" + (kSource / "graphs/refraction_hybrid.json").string() + "'";
  const CliRun camera = run("render --graph " + hybrid + sphere + " --size 64x36 --out c.png --stats c.json", dir);
  const CliRun asked = run("render --tracer ray_query --graph " + raytraced + sphere + small + " --out y.png", dir);
  ::setenv("CAUSTICA_TRACER", "ray_query", 1);
  const CliRun asked_validate = run("validate " + raytraced, dir);
  ::unsetenv("CAUSTICA_TRACER");
  ::unsetenv("CAUSTICA_NO_RAY_QUERY");
  EXPECT_EQ(validate.code, 0) << validate.output;
  ASSERT_EQ(render.code, 0) << render.output;
  const auto traced_stats = nlohmann::json::parse(read(dir / "x.json"));
  EXPECT_EQ(traced_stats.value("tracer", ""), "compute");
  EXPECT_GT(traced_stats["counters"]["photons.exact"].get<double>(), 0.0);
  ASSERT_EQ(camera.code, 0) << camera.output;
  EXPECT_EQ(nlohmann::json::parse(read(dir / "c.json")).value("tracer", ""), "compute");
  for (const CliRun* r : {&asked, &asked_validate}) {
    EXPECT_EQ(r->code, 1) << r->output;
    EXPECT_NE(r->output.find("caustics_raytraced.json:"), std::string::npos) << r->output;
    EXPECT_NE(r->output.find("pass 'caustics#0' (caustic_map)"), std::string::npos) << r->output;
    EXPECT_NE(r->output.find("VK_KHR_ray_query"), std::string::npos) << r->output;
    EXPECT_NE(r->output.find("--tracer compute"), std::string::npos) << r->output;
  }
  EXPECT_FALSE(fs::exists(dir / "y.png"));
  const CliRun unknown = run("render --tracer optix --graph " + raytraced + sphere + small + " --out z.png", dir);
  EXPECT_EQ(unknown.code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("--tracer optix: expected ray_query, compute or auto"), std::string::npos) << unknown.output;
  // The plan, compiled without a device, reports the memory of the tracer it is given: the compute
  // tracer's BVH is built on the host, so its bytes are the render's to the byte; ray queries'
  // structures (where the device has them) are their inputs exactly and an estimate of the driver's
  // size.
  const CliRun compute_plan = run("graph plan " + raytraced + sphere + " --tracer compute", dir);
  ASSERT_EQ(compute_plan.code, 0) << compute_plan.output;
  const auto bvh = nlohmann::json::parse(compute_plan.output)["memory"]["bvh"];
  EXPECT_EQ(bvh["triangles"].get<double>(), 4018.0);  // ball 3968, floor 2, four checker boxes 12 each
  EXPECT_EQ(bvh["bytes"].get<double>(), traced_stats["memory"]["acceleration_bytes"].get<double>());
  const CliRun traced = run("render --tracer ray_query --graph " + raytraced + sphere + small + " --out x.png --stats s.json", dir);
  if (traced.code == 1 && traced.output.find("as the tracer asked for (ray_query), and this device lacks") != std::string::npos) {
    std::printf("this device has no ray queries: their plan's estimate is not compared\n");
    fs::remove_all(dir);
    return;
  }
  ASSERT_EQ(traced.code, 0) << traced.output;
  const auto stats = nlohmann::json::parse(read(dir / "s.json"));
  EXPECT_EQ(stats.value("tracer", ""), "ray_query");
  EXPECT_GT(stats["counters"]["photons.exact"].get<double>(), 0.0);
  const CliRun plan = run("graph plan " + raytraced + sphere, dir);
  ASSERT_EQ(plan.code, 0) << plan.output;
  const auto acceleration = nlohmann::json::parse(plan.output)["memory"]["acceleration"];
  const double held = stats["memory"]["acceleration_bytes"].get<double>();
  EXPECT_EQ(acceleration["triangles"].get<double>(), 4018.0);
  EXPECT_LT(acceleration["input_bytes"].get<double>(), held);
  EXPECT_GT(acceleration["bytes_estimate"].get<double>(), 0.5 * held);
  EXPECT_LT(acceleration["bytes_estimate"].get<double>(), 2.0 * held);
  const CliRun image_space_plan = run("graph plan '" + (kSource / "graphs/caustics_adaptive.json").string() + "'" + sphere, dir);
  ASSERT_EQ(image_space_plan.code, 0) << image_space_plan.output;
  EXPECT_FALSE(nlohmann::json::parse(image_space_plan.output)["memory"].contains("acceleration"));
  fs::remove_all(dir);
}
