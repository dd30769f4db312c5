// CPU-only compiler tests: no device, the test registry declares pass types without device code.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <regex>

#include "builtin_passes.h"
#include "graph/compiler.h"
#include "graph/expression.h"
#include "test_registry.h"

using namespace caustica;
using namespace caustica::graph;

namespace {

const PassRegistry& registry() {
  static const PassRegistry r = test::make_test_registry();
  return r;
}

GraphDesc graph_from(const nlohmann::json& j) {
  return load_graph(JsonDocument::parse(j.dump(2), "test.json"));
}

Plan compile(const nlohmann::json& j, CompileOptions options = {}) {
  options.output_width = 64;
  options.output_height = 32;
  return compile_graph(graph_from(j), registry(), options);
}

std::string compile_error(const nlohmann::json& j, CompileOptions options = {}) {
  try {
    compile(j, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

nlohmann::json image(const char* format = "rgba16f") {
  return {{"type", "image"}, {"format", format}};
}

std::vector<std::string> order(const Plan& plan) {
  std::vector<std::string> names;
  for (const auto& p : plan.passes) names.push_back(p.name);
  return names;
}

// A chain src -> f1 -> f2 -> f3 -> out, plus a pass that reaches no output.
nlohmann::json chain() {
  return {{"resources", {{"a", image()}, {"b", image()}, {"c", image()}, {"out", image("rgba8")}, {"unused", image()}}},
          {"passes",
           {{{"name", "f3"}, {"type", "filter"}, {"inputs", {{"source", "c"}}}, {"outputs", {{"target", "out"}}}},
            {{"name", "src"}, {"type", "source"}, {"outputs", {{"color", "a"}}}},
            {{"name", "dead"}, {"type", "filter"}, {"inputs", {{"source", "a"}}}, {"outputs", {{"target", "unused"}}}},
            {{"name", "f1"}, {"type", "filter"}, {"inputs", {{"source", "a"}}}, {"outputs", {{"target", "b"}}}},
            {{"name", "f2"}, {"type", "filter"}, {"inputs", {{"source", "b"}}}, {"outputs", {{"target", "c"}}}}}},
          {"outputs", {"out"}}};
}

}  // namespace

TEST(Compiler, OrdersByDependencyAndCullsDeadPasses) {
  Plan plan = compile(chain());
  EXPECT_EQ(order(plan), (std::vector<std::string>{"src", "f1", "f2", "f3"}));
  EXPECT_EQ(plan.culled, std::vector<std::string>{"dead"});
  EXPECT_FALSE(plan.resources[static_cast<size_t>(plan.find_resource("unused"))].used());
}

TEST(Compiler, SideEffectPassesSurviveCulling) {
  auto g = chain();
  g["passes"].push_back({{"name", "probe"}, {"type", "report"}, {"inputs", {{"source", "unused"}}}});
  Plan plan = compile(g);
  EXPECT_TRUE(plan.culled.empty());
  auto names = order(plan);
  auto pos = [&](const char* n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
  EXPECT_LT(pos("dead"), pos("probe"));
  EXPECT_LT(pos("src"), pos("dead"));
}

TEST(Compiler, LifetimesSpanFirstToLastUse) {
  Plan plan = compile(chain());
  auto lifetime = [&](const char* n) {
    const auto& r = plan.resources[static_cast<size_t>(plan.find_resource(n))];
    return std::pair{r.first_use, r.last_use};
  };
  EXPECT_EQ(lifetime("a"), (std::pair{0u, 1u}));
  EXPECT_EQ(lifetime("b"), (std::pair{1u, 2u}));
  EXPECT_EQ(lifetime("c"), (std::pair{2u, 3u}));
}

TEST(Compiler, DisjointLifetimesShareMemory) {
  Plan plan = compile(chain());
  const auto& a = plan.resources[static_cast<size_t>(plan.find_resource("a"))];
  const auto& c = plan.resources[static_cast<size_t>(plan.find_resource("c"))];
  EXPECT_EQ(a.block, c.block);
  EXPECT_EQ(a.offset, c.offset);  // a dies at f1, c is born at f2
  EXPECT_LT(plan.transient_bytes_aliased, plan.transient_bytes_unaliased);
  EXPECT_EQ(plan.transient_bytes_unaliased, 3 * estimate_memory_requirements(a).size);
  EXPECT_EQ(plan.transient_bytes_aliased, 2 * estimate_memory_requirements(a).size);

  CompileOptions no_alias;
  no_alias.alias = false;
  Plan unaliased = compile(chain(), no_alias);
  EXPECT_EQ(unaliased.transient_bytes_aliased, unaliased.transient_bytes_unaliased);
}

// File order makes 'early' hold X while the chain runs (three images live at once); running the
// chain first and 'early' just before its reader needs two.
TEST(Compiler, OrderKeepsTheLeastPeakMemory) {
  nlohmann::json g = {{"resources", {{"x", image()}, {"y", image()}, {"z", image()}, {"out", image()}}},
                      {"passes",
                       {{{"name", "early"}, {"type", "source"}, {"outputs", {{"color", "x"}}}},
                        {{"name", "chain1"}, {"type", "source"}, {"outputs", {{"color", "y"}}}},
                        {{"name", "chain2"}, {"type", "filter"}, {"inputs", {{"source", "y"}}}, {"outputs", {{"target", "z"}}}},
                        {{"name", "final"}, {"type", "blend"}, {"inputs", {{"a", "x"}, {"b", "z"}}}, {"outputs", {{"color", "out"}}}}}},
                      {"outputs", {"out"}}};
  Plan plan = compile(g);
  EXPECT_EQ(order(plan), (std::vector<std::string>{"chain1", "chain2", "early", "final"}));
  const uint64_t one = estimate_memory_requirements(plan.resources[static_cast<size_t>(plan.find_resource("x"))]).size;
  EXPECT_EQ(plan.transient_bytes_unaliased, 3 * one);
  EXPECT_EQ(plan.transient_bytes_aliased, 2 * one);
  // Where file order is already as good, it is kept.
  EXPECT_EQ(order(compile(chain())), (std::vector<std::string>{"src", "f1", "f2", "f3"}));
}

TEST(Compiler, AliasedFirstUseWaitsForThePreviousTenant) {
  Plan plan = compile(chain());
  int c = plan.find_resource("c");
  const auto& f2 = plan.passes[2];
  auto it =
      std::find_if(f2.barriers.begin(), f2.barriers.end(), [&](const PlannedBarrier& b) { return b.resource == static_cast<uint32_t>(c); });
  ASSERT_NE(it, f2.barriers.end());
  EXPECT_TRUE(it->aliasing);
  EXPECT_EQ(it->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_NE(it->src_stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, 0u);  // f1 sampled 'a' in a compute shader
}

TEST(Compiler, RetainedResourcesAreNotAliased) {
  CompileOptions options;
  options.retained = {"a"};
  Plan plan = compile(chain(), options);
  const auto& a = plan.resources[static_cast<size_t>(plan.find_resource("a"))];
  EXPECT_FALSE(a.transient);
  EXPECT_EQ(a.block, kNoBlock);
  EXPECT_NE(a.image_usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 0u);
}

TEST(Compiler, AnOptionalOutputNobodyReadsStaysUnbound) {
  nlohmann::json g = {{"resources", {{"debug", image()}, {"x", image()}, {"out", image()}}},
                      {"passes",
                       {{{"name", "a"}, {"type", "node"}, {"outputs", {{"out0", "debug"}, {"out1", "x"}}}},
                        {{"name", "b"}, {"type", "filter"}, {"inputs", {{"source", "x"}}}, {"outputs", {{"target", "out"}}}}}},
                      {"outputs", {"out"}}};
  auto pass_a = [](const Plan& plan) {
    return *std::find_if(plan.passes.begin(), plan.passes.end(), [](const auto& p) { return p.name == "a"; });
  };
  auto debug_bound = [&](const Plan& plan) {
    return pass_a(plan).ports.count("out0") != 0 && plan.resources[static_cast<size_t>(plan.find_resource("debug"))].used();
  };
  EXPECT_FALSE(debug_bound(compile(g)));
  EXPECT_EQ(pass_a(compile(g)).ports.count("out1"), 1u);
  CompileOptions kept;
  kept.retained = {"debug"};
  EXPECT_TRUE(debug_bound(compile(g, kept)));
  g["outputs"].push_back("debug");
  EXPECT_TRUE(debug_bound(compile(g)));
  g["outputs"] = {"out"};
  g["passes"].push_back({{"name", "c"}, {"type", "report"}, {"inputs", {{"source", "debug"}}}});
  EXPECT_TRUE(debug_bound(compile(g)));
}

TEST(Compiler, ReportsCycleWithItsPath) {
  nlohmann::json g = {{"resources", {{"x", image()}, {"y", image()}, {"out", image()}}},
                      {"passes",
                       {{{"name", "a"}, {"type", "filter"}, {"inputs", {{"source", "y"}}}, {"outputs", {{"target", "x"}}}},
                        {{"name", "b"}, {"type", "filter"}, {"inputs", {{"source", "x"}}}, {"outputs", {{"target", "y"}}}},
                        {{"name", "c"}, {"type", "filter"}, {"inputs", {{"source", "y"}}}, {"outputs", {{"target", "out"}}}}}},
                      {"outputs", {"out"}}};
  std::string message = compile_error(g);
  EXPECT_NE(message.find("cycle: a -> b -> a"), std::string::npos) << message;
  EXPECT_NE(message.find("test.json:"), std::string::npos) << message;
}

TEST(Compiler, TwoUnorderedWritersAreAnErrorUntilOrdered) {
  nlohmann::json g = {{"resources", {{"x", image()}}},
                      {"passes",
                       {{{"name", "w"}, {"type", "source"}, {"outputs", {{"color", "x"}}}},
                        {{"name", "p"}, {"type", "accumulate"}, {"outputs", {{"target", "x"}}}},
                        {{"name", "q"}, {"type", "accumulate"}, {"outputs", {{"target", "x"}}}}}},
                      {"outputs", {"x"}}};
  std::string message = compile_error(g);
  EXPECT_NE(message.find("written by passes 'w' and 'p' with no order"), std::string::npos) << message;
  EXPECT_NE(message.find("(at /passes/1/outputs/target)"), std::string::npos) << message;
  g["passes"][1]["after"] = {"w"};
  g["passes"][2]["after"] = {"p"};
  Plan plan = compile(g);
  EXPECT_EQ(order(plan), (std::vector<std::string>{"w", "p", "q"}));
  // q writes after p wrote the same storage image: a write-after-write barrier.
  ASSERT_EQ(plan.passes[2].barriers.size(), 1u);
  EXPECT_EQ(plan.passes[2].barriers[0].src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(Compiler, ValidatesPortsFormatsAndExtents) {
  auto g = chain();
  g["resources"]["b"] = image("r32ui");
  EXPECT_NE(compile_error(g).find("format mismatch: port 'target' of pass 'f1' accepts rgba16f, rgba32f, rgba8, but 'b' is r32ui"),
            std::string::npos);

  g = chain();
  g["passes"][3]["inputs"] = nlohmann::json::object();
  EXPECT_NE(compile_error(g).find("input 'source' of pass 'f1' (type filter) is not connected"), std::string::npos);

  g = chain();
  g["passes"][3]["inputs"]["sourse"] = "a";
  EXPECT_NE(compile_error(g).find("has no port 'sourse' (did you mean 'source'?)"), std::string::npos);

  g = chain();
  g["passes"][1]["type"] = "sorce";
  EXPECT_NE(compile_error(g).find("unknown pass type 'sorce' (did you mean 'source'?)"), std::string::npos);

  nlohmann::json blend = {{"resources", {{"a", image()}, {"b", image()}, {"out", image()}}},
                          {"passes",
                           {{{"name", "s1"}, {"type", "source"}, {"outputs", {{"color", "a"}}}},
                            {{"name", "s2"}, {"type", "source"}, {"outputs", {{"color", "b"}}}},
                            {{"name", "mix"}, {"type", "blend"}, {"inputs", {{"a", "a"}, {"b", "b"}}}, {"outputs", {{"color", "out"}}}}}},
                          {"outputs", {"out"}}};
  EXPECT_EQ(order(compile(blend)).size(), 3u);
  blend["resources"]["b"]["width"] = "output.width / 2";
  EXPECT_NE(compile_error(blend).find("extent mismatch in pass 'mix': 'b' (port 'b') is 32x32 but 'a' (port 'a') is 64x32"),
            std::string::npos)
      << compile_error(blend);
}

// Array layers: a port that takes three layers (the caustic map's colour channels) refuses an
// image of one and a one-layer port refuses three; only r32f images have layers; the memory and
// the plan count every layer.
TEST(Compiler, LayeredImagesMatchTheirPorts) {
  nlohmann::json layered = image("r32f");
  layered["layers"] = 3;
  nlohmann::json g = {{"resources", {{"map", layered}, {"c", image()}}},
                      {"passes", {{{"name", "s"}, {"type", "splat"}, {"outputs", {{"target", "map"}, {"color", "c"}}}}}},
                      {"outputs", {"c"}}};
  const Plan plan = compile(g);
  const PlannedResource& map = plan.resources[static_cast<size_t>(plan.find_resource("map"))];
  EXPECT_EQ(map.layers, 3u);
  PlannedResource one = map;
  one.layers = 1;
  EXPECT_EQ(estimate_memory_requirements(map).size, 3 * estimate_memory_requirements(one).size);
  EXPECT_EQ(plan_to_json(plan)["resources"][static_cast<size_t>(plan.find_resource("map"))]["layers"], 3);

  g["resources"]["map"].erase("layers");
  EXPECT_NE(compile_error(g).find("layer mismatch: port 'target' of pass 's' takes an image of 3 array layers, but 'map' has 1"),
            std::string::npos)
      << compile_error(g);

  g["resources"]["map"]["layers"] = 3;
  g["passes"].push_back({{"name", "r"}, {"type", "report"}, {"inputs", {{"source", "map"}}}});
  EXPECT_NE(compile_error(g).find("layer mismatch: port 'source' of pass 'r' takes an image of 1 layer, but 'map' has 3"),
            std::string::npos)
      << compile_error(g);

  g["passes"].erase(1);
  g["resources"]["c"]["layers"] = 2;
  EXPECT_NE(compile_error(g).find("'c' is rgba16f; only r32f and d32f images can have layers (at /resources/c/layers)"), std::string::npos)
      << compile_error(g);
  g["resources"]["c"] = layered;
  g["resources"]["c"]["layers"] = 7;
  EXPECT_NE(compile_error(g).find("'c' asks for 7 array layers; an image has 1 to 6"), std::string::npos) << compile_error(g);
}

TEST(Compiler, ParametersResolveDefaultsReferencesAndRanges) {
  auto g = chain();
  g["parameters"] = {{"blur", {{"type", "int"}, {"default", 3}, {"min", 0}, {"max", 8}}}};
  g["passes"][3]["params"] = {{"radius", "$blur"}};
  Plan plan = compile(g);
  EXPECT_EQ(plan.passes[1].params["radius"], 3);
  EXPECT_EQ(plan.passes[0].params["gain"], 1.0);  // declared default

  auto desc = graph_from(g);
  apply_overrides(desc, {"blur=7"});
  CompileOptions options;
  EXPECT_EQ(compile_graph(desc, registry(), options).passes[1].params["radius"], 7);
  EXPECT_THROW(apply_overrides(desc, {"blur=9"}), InputError);
  EXPECT_THROW(apply_overrides(desc, {"blur=1.5"}), InputError);
  try {
    apply_overrides(desc, {"blurr=1"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'blur'"), std::string::npos);
  }

  g["passes"][3]["params"] = {{"radios", 2}};
  EXPECT_NE(compile_error(g).find("has no parameter 'radios' (did you mean 'radius'?)"), std::string::npos);
  g["passes"][3]["params"] = {{"radius", 17}};
  EXPECT_NE(compile_error(g).find("above its maximum 16"), std::string::npos);
}

TEST(Compiler, ExtentsAndMemoryLimits) {
  auto g = chain();
  g["resources"]["b"]["width"] = "output.width * 1000";
  EXPECT_NE(compile_error(g).find("above the device limit of 16384"), std::string::npos);
  g["resources"]["b"]["width"] = "output.width - 64";
  EXPECT_NE(compile_error(g).find("it must be at least 1"), std::string::npos);
  g["resources"]["b"]["width"] = "output.widht";
  EXPECT_NE(compile_error(g).find("unknown name 'output.widht' (did you mean 'output.width'?)"), std::string::npos);

  CompileOptions tight;
  tight.memory_limit_bytes = 20000;
  std::string message = compile_error(chain(), tight);
  EXPECT_NE(message.find("above the limit of"), std::string::npos) << message;
  EXPECT_NE(message.find("largest: 'a'"), std::string::npos) << message;
}

TEST(Expression, Arithmetic) {
  ExpressionScope scope;
  scope.known_names = {"w"};
  scope.lookup = [](std::string_view n) -> std::optional<double> { return n == "w" ? std::optional(640.0) : std::nullopt; };
  EXPECT_EQ(evaluate_expression("w / 2 + 1", scope), 321);
  EXPECT_EQ(evaluate_expression("max(1, w / 1024)", scope), 1);
  EXPECT_EQ(evaluate_expression("-(2 + 3) * 4 % 7", scope), -6);
  EXPECT_EQ(evaluate_expression("pow(2, 10)", scope), 1024);
  EXPECT_THROW(evaluate_expression("w / 0", scope), std::invalid_argument);
  EXPECT_THROW(evaluate_expression("w +", scope), std::invalid_argument);
  EXPECT_THROW(evaluate_expression("maxx(1, 2)", scope), std::invalid_argument);
  EXPECT_THROW(evaluate_expression("pow(10, 400)", scope), std::invalid_argument);
  EXPECT_THROW(evaluate_expression(std::string(200, '('), scope), std::invalid_argument);
}

TEST(JsonDocument, LocatesValuesAndRejectsWhatNlohmannAccepts) {
  auto doc = JsonDocument::parse("{\n  \"a\": [1,\n    {\"b\": true}]\n}\n", "f.json");
  EXPECT_EQ(doc.locate("/a/1/b").line, 3);
  EXPECT_EQ(doc.locate("/a/1/b").column, 11);
  EXPECT_EQ(doc.locate("/a/1/missing").line, 3);  // nearest ancestor
  EXPECT_THROW(JsonDocument::parse("{\"a\": 1, \"a\": 2}", "f.json"), InputError);
  EXPECT_THROW(JsonDocument::parse(std::string(1000, '['), "f.json"), InputError);
  EXPECT_THROW(JsonDocument::parse("{\"a\": 1e999}", "f.json"), InputError);
  EXPECT_THROW(JsonDocument::parse("{\"a\": NaN}", "f.json"), InputError);
  try {
    JsonDocument::parse("{\n\"a\": [1, 2,\n]}", "f.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("f.json:3:1: invalid JSON", 0), 0u) << e.what();
  }
  EXPECT_EQ(JsonDocument::parse("\"\\ud83d\\ude00\"", "f").root().get<std::string>(), "\xF0\x9F\x98\x80");
}

// ---- randomly generated graphs --------------------------------------------------------------

namespace {

nlohmann::json random_graph(std::mt19937& rng, int passes) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  nlohmann::json resources = nlohmann::json::object();
  nlohmann::json list = nlohmann::json::array();
  std::vector<std::string> images, buffers;
  const char* formats[] = {"rgba8", "rgba16f", "rgba32f", "r32f"};
  for (int p = 0; p < passes; ++p) {
    nlohmann::json pass = {
        {"name", "p" + std::to_string(p)}, {"type", "node"}, {"inputs", nlohmann::json::object()}, {"outputs", nlohmann::json::object()}};
    std::set<std::string> used;
    for (int i = 0, n = images.empty() ? 0 : pick(4) + (p > 0); i < n && i < 4; ++i) {
      const auto& r = images[static_cast<size_t>(pick(static_cast<int>(images.size())))];
      if (used.insert(r).second) pass["inputs"]["in" + std::to_string(i)] = r;
    }
    for (int i = 0, n = buffers.empty() ? 0 : pick(3); i < n && i < 2; ++i) {
      const auto& r = buffers[static_cast<size_t>(pick(static_cast<int>(buffers.size())))];
      if (used.insert(r).second) pass["inputs"]["bin" + std::to_string(i)] = r;
    }
    for (int i = 0, n = 1 + pick(2); i < n; ++i) {
      std::string name = "img" + std::to_string(p) + "_" + std::to_string(i);
      resources[name] = {
          {"type", "image"}, {"format", formats[pick(4)]}, {"width", 1 + pick(512)}, {"height", 1 + pick(512)}, {"mips", 1 + pick(3)}};
      pass["outputs"]["out" + std::to_string(i)] = name;
      images.push_back(name);
    }
    if (pick(3) == 0) {
      std::string name = "buf" + std::to_string(p);
      resources[name] = {{"type", "buffer"}, {"size", 4 + pick(1 << 20)}};
      pass["outputs"]["bout0"] = name;
      buffers.push_back(name);
    }
    list.push_back(pass);
  }
  nlohmann::json outputs = {images.back()};
  for (int i = 0; i < 2; ++i) {
    auto candidate = images[static_cast<size_t>(pick(static_cast<int>(images.size())))];
    if (candidate != images.back() && std::find(outputs.begin(), outputs.end(), candidate) == outputs.end()) outputs.push_back(candidate);
  }
  return {{"resources", resources}, {"passes", list}, {"outputs", outputs}};
}

// Independent checks of a plan: no two resources alive in the same pass overlap in memory,
// placements respect alignment and block sizes, the order respects every read, every read
// of a write is preceded by a barrier covering it, and layouts chain from barrier to barrier.
void check_plan(const Plan& plan) {
  for (size_t i = 0; i < plan.resources.size(); ++i) {
    const auto& a = plan.resources[i];
    if (!a.used() || !a.transient) continue;
    ASSERT_LT(a.block, plan.blocks.size());
    EXPECT_EQ(a.offset % a.memory.alignment, 0u);
    EXPECT_LE(a.offset + a.memory.size, plan.blocks[a.block].size);
    for (size_t j = i + 1; j < plan.resources.size(); ++j) {
      const auto& b = plan.resources[j];
      if (!b.used() || !b.transient || a.block != b.block) continue;
      bool lifetimes_overlap = a.first_use <= b.last_use && b.first_use <= a.last_use;
      bool memory_overlaps = a.offset < b.offset + b.memory.size && b.offset < a.offset + a.memory.size;
      EXPECT_FALSE(lifetimes_overlap && memory_overlaps) << a.name << " and " << b.name << " share memory while both alive";
    }
  }
  uint64_t sum = 0;
  for (const auto& b : plan.blocks) sum += b.size;
  EXPECT_EQ(sum, plan.transient_bytes_aliased);
  EXPECT_LE(plan.transient_bytes_aliased, plan.transient_bytes_unaliased);

  std::map<uint32_t, uint32_t> last_write;  // resource -> pass index
  std::map<uint32_t, VkImageLayout> layout;
  for (uint32_t p = 0; p < plan.passes.size(); ++p) {
    const auto& pass = plan.passes[p];
    for (const auto& b : pass.barriers) {
      if (plan.resources[b.resource].kind != ResourceKind::image) continue;
      VkImageLayout expected = layout.count(b.resource) ? layout[b.resource] : VK_IMAGE_LAYOUT_UNDEFINED;
      EXPECT_EQ(b.old_layout, expected) << pass.name << " " << plan.resources[b.resource].name;
      layout[b.resource] = b.new_layout;
    }
    for (const auto& [port, r] : pass.ports) {
      const PortDecl* decl = pass.decl->find_port(port);
      if (decl->access == PortAccess::read) {
        ASSERT_TRUE(last_write.count(r)) << pass.name << " reads " << plan.resources[r].name << " before it is written";
        // Some barrier at or after the writer's successor and up to this pass makes the write visible here.
        bool synced = false;
        for (uint32_t q = last_write[r] + 1; q <= p && !synced; ++q) {
          for (const auto& b : plan.passes[q].barriers) {
            synced = synced || (b.resource == r && (b.dst_stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT) &&
                                (b.src_access & VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) != 0);
          }
        }
        EXPECT_TRUE(synced) << pass.name << " reads " << plan.resources[r].name << " without a barrier after its write";
      } else {
        last_write[r] = p;
      }
    }
  }
}

}  // namespace

TEST(Compiler, RandomGraphsNeverOverlapLiveMemoryAndAlwaysSynchronize) {
  std::mt19937 rng(12345);
  int compiled = 0;
  uint64_t saved = 0;
  for (int i = 0; i < 300; ++i) {
    auto g = random_graph(rng, 2 + static_cast<int>(rng() % 40));
    CompileOptions options;
    options.memory_limit_bytes = ~0ull;
    Plan plan = compile(g, options);
    SCOPED_TRACE("graph " + std::to_string(i));
    check_plan(plan);
    saved += plan.transient_bytes_unaliased - plan.transient_bytes_aliased;
    ++compiled;
  }
  EXPECT_EQ(compiled, 300);
  EXPECT_GT(saved, 0u);  // aliasing must actually happen on these graphs
}

namespace {

// The peak of live transient bytes over `order` (positions into plan.passes), or nothing when the
// order runs a reader before a writer of what it reads.
std::optional<uint64_t> peak_bytes(const Plan& plan, const std::vector<size_t>& order) {
  std::map<uint32_t, std::pair<size_t, size_t>> span;  // resource -> first and last position
  std::map<uint32_t, size_t> last_write, first_read;
  for (size_t at = 0; at < order.size(); ++at) {
    const auto& pass = plan.passes[order[at]];
    for (const auto& [port, r] : pass.ports) {
      auto [it, fresh] = span.try_emplace(r, at, at);
      it->second.second = at;
      if (pass.decl->find_port(port)->access == PortAccess::read)
        first_read.try_emplace(r, at);
      else
        last_write[r] = at;
    }
  }
  for (const auto& [r, at] : first_read) {
    if (last_write.count(r) && last_write[r] > at) return std::nullopt;
  }
  uint64_t peak = 0;
  for (size_t at = 0; at < order.size(); ++at) {
    uint64_t live = 0;
    for (const auto& [r, s] : span)
      live += plan.resources[r].transient && s.first <= at && at <= s.second ? plan.resources[r].memory.size : 0;
    peak = std::max(peak, live);
  }
  return peak;
}

// A number may be an expression: of the output size, the scene and the graph's parameters,
// evaluated once; and for a parameter the pass reads while recording (ParamDecl::per_frame), of the
// frame block, which the executor evaluates before every frame: the plan keeps the first frame's
// value, the expression and what it names, and the pass then depends on the frame.
TEST(Compiler, ParametersMayBeExpressionsOfTheFrame) {
  const nlohmann::json graph = {
      {"parameters", {{"strength", {{"type", "float"}, {"default", 2.0}, {"min", 0.0}, {"max", 5.0}}}}},
      {"resources", {{"lit", image()}, {"out", image()}}},
      {"passes",
       {{{"name", "light"}, {"type", "source"}, {"params", {{"gain", "strength * output.width / 64"}}}, {"outputs", {{"color", "lit"}}}},
        {{"name", "blur"},
         {"type", "filter"},
         {"params", {{"radius", "min(8, 3 + frame.since_reset / 2)"}}},
         {"inputs", {{"source", "lit"}}},
         {"outputs", {{"target", "out"}}}}}},
      {"outputs", {"out"}}};
  const Plan plan = compile(graph);
  const PlannedPass& light = plan.passes[0];
  const PlannedPass& blur = plan.passes[1];
  ASSERT_EQ(blur.name, "blur");
  EXPECT_EQ(light.params["gain"], 2.0);  // 2 * 64 / 64
  EXPECT_TRUE(light.frame_params.empty());
  EXPECT_EQ(dependency_names(light.depends), (std::vector<std::string>{"geometry", "lights"}));
  EXPECT_EQ(blur.params["radius"], 3);  // the first frame's, an integer
  EXPECT_EQ(blur.frame_params, (std::map<std::string, std::string>{{"radius", "min(8, 3 + frame.since_reset / 2)"}}));
  EXPECT_EQ(dependency_names(blur.depends), (std::vector<std::string>{"geometry", "lights", "frame"}));
  EXPECT_EQ(plan.expression_values.at("strength"), 2.0);
  EXPECT_EQ(plan.expression_values.at("output.height"), 32.0);
  EXPECT_EQ(plan_to_json(plan)["passes"][1]["frame_params"]["radius"], "min(8, 3 + frame.since_reset / 2)");

  nlohmann::json rounded = graph;  // an integer parameter rounds down
  rounded["passes"][1]["params"]["radius"] = "output.height / 5";
  EXPECT_EQ(compile(rounded).passes[1].params["radius"], 6);
  EXPECT_TRUE(compile(rounded).passes[1].frame_params.empty());

  nlohmann::json set_up = graph;
  set_up["passes"][0]["params"]["gain"] = "1 + frame.index";
  EXPECT_NE(compile_error(set_up).find("/passes/0/params/gain"), std::string::npos) << compile_error(set_up);
  EXPECT_NE(compile_error(set_up).find("parameter 'gain' of pass 'light' is fixed for a plan, so \"1 + frame.index\" cannot "
                                       "follow the frame; no parameter of pass type 'source' can"),
            std::string::npos)
      << compile_error(set_up);
  nlohmann::json misspelt = graph;
  misspelt["passes"][1]["params"]["radius"] = "frame.since_rest";
  EXPECT_NE(compile_error(misspelt).find("unknown name 'frame.since_rest' (did you mean 'frame.since_reset'?)"), std::string::npos)
      << compile_error(misspelt);
  nlohmann::json too_bright = graph;
  too_bright["passes"][0]["params"]["gain"] = "output.width";
  EXPECT_NE(compile_error(too_bright).find("parameter 'gain' of pass 'light' is 64, above its maximum 10 (\"output.width\")"),
            std::string::npos)
      << compile_error(too_bright);
  nlohmann::json infinite = graph;
  infinite["passes"][1]["params"]["radius"] = "1 / frame.index";
  EXPECT_NE(compile_error(infinite).find("\"1 / frame.index\" at character 16: division by zero (at /passes/1/params/radius)"),
            std::string::npos)
      << compile_error(infinite);
}

// One run reports every independent error, a line each in the order of the file: here a pass with
// two unknown parameters and an unknown port, and another of an unknown type; and, when loading,
// two resources with unknown formats. A pass with a refused binding (the misspelt port) is not
// reported again for the port it left unconnected.
TEST(Compiler, EveryIndependentErrorIsReportedInOneRun) {
  const nlohmann::json graph = {
      {"resources", {{"lit", image()}, {"out", image()}}},
      {"passes",
       {{{"name", "light"}, {"type", "source"}, {"params", {{"gian", 2.0}, {"mood", "a"}}}, {"outputs", {{"colour", "lit"}}}},
        {{"name", "show"}, {"type", "fliter"}, {"inputs", {{"source", "lit"}}}, {"outputs", {{"target", "out"}}}}}},
      {"outputs", {"out"}}};
  const std::string message = compile_error(graph);
  // (The test's file is written with its keys sorted: "outputs" before "params".)
  const std::vector<std::string> expected = {
      "has no port 'colour' (did you mean 'color'?)", "has no parameter 'gian' (did you mean 'gain'?)",
      "has no parameter 'mood' (did you mean 'mode'?)", "unknown pass type 'fliter' (did you mean 'filter'?)"};
  size_t at = 0;
  for (const auto& e : expected) {
    const size_t found = message.find(e, at);
    EXPECT_NE(found, std::string::npos) << "missing or out of order: " << e << "\n" << message;
    if (found != std::string::npos) at = found;
  }
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 3) << message;
  EXPECT_EQ(message.find("not connected"), std::string::npos) << message;

  nlohmann::json formats = graph;
  formats["resources"]["lit"]["format"] = "rgba17f";
  formats["resources"]["out"]["format"] = "rgb8";
  const std::string load_message = compile_error(formats);
  EXPECT_NE(load_message.find("unknown format 'rgba17f'"), std::string::npos) << load_message;
  EXPECT_NE(load_message.find("unknown format 'rgb8'"), std::string::npos) << load_message;
}

}  // namespace

// Against every order a small graph allows, tried one by one: none has a lower peak.
TEST(Compiler, NoValidOrderHasALowerPeakThanThePlans) {
  std::mt19937 rng(777);
  int checked = 0, reordered = 0;
  for (int i = 0; i < 300 && checked < 60; ++i) {
    CompileOptions options;
    options.memory_limit_bytes = ~0ull;
    Plan plan = compile(random_graph(rng, 3 + static_cast<int>(rng() % 5)), options);
    if (plan.passes.size() < 3 || plan.passes.size() > 7) continue;
    std::vector<size_t> order(plan.passes.size());
    std::iota(order.begin(), order.end(), 0);
    const uint64_t planned = *peak_bytes(plan, order);
    uint64_t least = planned;
    while (std::next_permutation(order.begin(), order.end())) {
      if (auto peak = peak_bytes(plan, order)) least = std::min(least, *peak);
    }
    EXPECT_EQ(planned, least) << "graph " << i;
    ++checked;
    std::vector<std::string> names = ::order(plan);
    reordered += std::is_sorted(names.begin(), names.end(),
                                [](const std::string& a, const std::string& b) { return std::stoi(a.substr(1)) < std::stoi(b.substr(1)); })
                     ? 0
                     : 1;
  }
  EXPECT_EQ(checked, 60);
  EXPECT_GT(reordered, 0);  // the search did move passes on some of them
}

// A pass that only makes sense for some scenes: "enabled" is an expression over scene values, and a
// resource that no enabled pass writes is replaced by its fallback wherever it is read.
nlohmann::json scene_dependent() {
  return {{"resources",
           {{"lit", image()},
            {"refracted", {{"type", "image"}, {"format", "rgba16f"}, {"fallback", "lit"}}},
            {"scratch", image()},
            {"out", image("rgba8")}}},
          {"passes",
           {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
            {{"name", "layers"},
             {"type", "blend"},
             {"enabled", "scene.refractors"},
             {"inputs", {{"a", "lit"}, {"b", "scratch"}}},
             {"outputs", {{"color", "refracted"}}}},
            {{"name", "scratch_source"}, {"type", "source"}, {"enabled", "scene.refractors"}, {"outputs", {{"color", "scratch"}}}},
            {{"name", "tonemap"}, {"type", "filter"}, {"inputs", {{"source", "refracted"}}}, {"outputs", {{"target", "out"}}}}}},
          {"outputs", {"out"}}};
}

TEST(Compiler, ScenesWithoutRefractorsBuildNoRefractionPassOrResource) {
  CompileOptions none, two;
  none.scene_values = {{"scene.refractors", 0}};
  two.scene_values = {{"scene.refractors", 2}};
  Plan without = compile(scene_dependent(), none);
  EXPECT_EQ(order(without), (std::vector<std::string>{"light", "tonemap"}));
  EXPECT_EQ(without.disabled, (std::vector<std::string>{"layers", "scratch_source"}));
  EXPECT_EQ(without.fallbacks.at("refracted"), "lit");
  EXPECT_FALSE(without.resources[static_cast<size_t>(without.find_resource("scratch"))].used());
  EXPECT_FALSE(without.resources[static_cast<size_t>(without.find_resource("refracted"))].used());
  EXPECT_EQ(without.passes.back().ports.count("source"), 1u);
  EXPECT_EQ(without.resources[without.passes.back().ports.at("source")].name, "lit");
  EXPECT_EQ(without.resolve("refracted"), "lit");

  Plan with = compile(scene_dependent(), two);
  EXPECT_EQ(order(with).size(), 4u);
  EXPECT_TRUE(with.fallbacks.empty());
  EXPECT_GT(with.transient_bytes_unaliased, without.transient_bytes_unaliased);
}

TEST(Compiler, FallbackAndEnabledErrorsNameTheProblem) {
  CompileOptions none;
  none.scene_values = {{"scene.refractors", 0}};
  auto g = scene_dependent();
  g["resources"]["refracted"]["fallback"] = "litt";
  EXPECT_NE(compile_error(g, none).find("fallback 'litt' of 'refracted' is not a resource of this graph (did you mean 'lit'?)"),
            std::string::npos)
      << compile_error(g, none);
  g = scene_dependent();
  g["resources"]["refracted"]["fallback"] = "out";
  EXPECT_NE(compile_error(g, none).find("fallback 'out' of 'refracted' must have the same format"), std::string::npos);
  g = scene_dependent();
  g["resources"]["lit"]["fallback"] = "refracted";
  g["passes"][0]["enabled"] = false;
  EXPECT_NE(compile_error(g, none).find("fallback cycle: lit -> refracted -> lit"), std::string::npos) << compile_error(g, none);
  g = scene_dependent();
  g["passes"][1]["enabled"] = "scene.refractor";
  EXPECT_NE(compile_error(g, none).find("did you mean 'scene.refractors'"), std::string::npos) << compile_error(g, none);
  // Without a scene, expressions about it are unknown names.
  EXPECT_NE(compile_error(scene_dependent()).find("scene.refractors"), std::string::npos);
}

// What each pass depends on: its own scene parts and its inputs' writers'; a pass that rewrites an
// earlier pass's result (read_write) makes that pass run whenever it does. With reuse on, what
// reusable passes write is kept, and a kept image's first barrier starts from the layout the last
// frame left it in instead of discarding it.
TEST(Compiler, PassesDependOnTheirInputsAndReusedResultsAreKept) {
  const nlohmann::json graph = {
      {"resources", {{"lit", image()}, {"filtered", image()}, {"viewed", image()}, {"out", image()}}},
      {"passes",
       {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
        {{"name", "camera"}, {"type", "source"}, {"params", {{"mode", "b"}}}, {"outputs", {{"color", "viewed"}}}},
        {{"name", "f"}, {"type", "filter"}, {"inputs", {{"source", "lit"}}}, {"outputs", {{"target", "filtered"}}}},
        {{"name", "mix"}, {"type", "blend"}, {"inputs", {{"a", "filtered"}, {"b", "viewed"}}}, {"outputs", {{"color", "out"}}}}}},
      {"outputs", {"out"}}};
  auto depends = [](const Plan& plan, const std::string& pass) {
    for (const auto& p : plan.passes) {
      if (p.name == pass) return dependency_names(p.depends);
    }
    return std::vector<std::string>{"(no pass " + pass + ")"};
  };
  const Plan plain = compile(graph);
  EXPECT_EQ(depends(plain, "light"), (std::vector<std::string>{"geometry", "lights"}));
  EXPECT_EQ(depends(plain, "f"), (std::vector<std::string>{"geometry", "lights"}));
  EXPECT_EQ(depends(plain, "camera"), (std::vector<std::string>{"camera"}));
  EXPECT_EQ(depends(plain, "mix"), (std::vector<std::string>{"geometry", "lights", "camera"}));
  const auto lit = static_cast<size_t>(plain.find_resource("lit"));
  EXPECT_TRUE(plain.resources[lit].transient);
  EXPECT_FALSE(plain.reuses_unchanged_passes);

  CompileOptions reuse;
  reuse.reuse_unchanged_passes = true;
  const Plan reused = compile(graph, reuse);
  for (const char* name : {"lit", "filtered", "viewed"})
    EXPECT_FALSE(reused.resources[static_cast<size_t>(reused.find_resource(name))].transient) << name;
  const PlannedBarrier& first = reused.passes[0].barriers.at(0);
  ASSERT_EQ(reused.resources[first.resource].name, reused.passes[0].name == "light" ? "lit" : "viewed");
  EXPECT_EQ(first.old_layout, reused.resources[first.resource].final_state.layout);
  EXPECT_NE(first.old_layout, VK_IMAGE_LAYOUT_UNDEFINED);

  nlohmann::json rewritten = graph;
  rewritten["passes"].push_back({{"name", "add"}, {"type", "accumulate"}, {"outputs", {{"target", "lit"}}}, {"after", {"light"}}});
  const Plan accumulating = compile(rewritten, reuse);
  EXPECT_EQ(depends(accumulating, "light"), (std::vector<std::string>{"geometry", "lights", "frame"}));
  for (const char* name : {"lit", "filtered"}) {
    EXPECT_TRUE(accumulating.resources[static_cast<size_t>(accumulating.find_resource(name))].transient)
        << name << " is rewritten every frame";
  }
}

namespace {

// A light pass, the mean of its images through a history input of the mean, and a pass showing it.
nlohmann::json mean_through_history() {
  return {{"resources", {{"lit", image()}, {"mean", image()}, {"out", image()}}},
          {"passes",
           {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
            {{"name", "average"}, {"type", "blend"}, {"inputs", {{"a", "lit"}, {"b", "mean@previous"}}}, {"outputs", {{"color", "mean"}}}},
            {{"name", "show"}, {"type", "filter"}, {"inputs", {{"source", "mean"}}}, {"outputs", {{"target", "out"}}}}}},
          {"outputs", {"out"}}};
}

}  // namespace

// In a plan that reuses unchanged passes, the passes that move a running result (a mean, a pass
// reading a history input) and those that write what they read refine; the others show. They can
// run apart only where every image a showing pass reads from a refining one is kept: the running
// result is, a pass that changes every frame is not.
TEST(Compiler, RefiningPassesRunApartFromThoseThatShowTheirResult) {
  const nlohmann::json graph = {
      {"resources", {{"lit", image()}, {"estimate", image()}, {"average", image()}, {"viewed", image()}, {"out", image()}}},
      {"passes",
       {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
        {{"name", "estimate"},
         {"type", "filter"},
         {"params", {{"radius", "frame.index % 2"}}},
         {"inputs", {{"source", "lit"}}},
         {"outputs", {{"target", "estimate"}}}},
        {{"name", "mean"}, {"type", "mean"}, {"inputs", {{"source", "estimate"}}}, {"outputs", {{"average", "average"}}}},
        {{"name", "camera"}, {"type", "source"}, {"params", {{"mode", "b"}}}, {"outputs", {{"color", "viewed"}}}},
        {{"name", "show"}, {"type", "blend"}, {"inputs", {{"a", "average"}, {"b", "viewed"}}}, {"outputs", {{"color", "out"}}}}}},
      {"outputs", {"out"}}};
  auto refining = [](const Plan& plan) {
    std::vector<std::string> names;
    for (const auto& p : plan.passes) {
      if (p.refines) names.push_back(p.name);
    }
    return names;
  };
  EXPECT_FALSE(compile(graph).refines_apart) << "only a plan that keeps results can leave passes out of a frame";
  CompileOptions reuse;
  reuse.reuse_unchanged_passes = true;
  const Plan plan = compile(graph, reuse);
  EXPECT_TRUE(plan.refines_apart);
  EXPECT_EQ(refining(plan), (std::vector<std::string>{"light", "estimate", "mean"}));
  EXPECT_FALSE(plan.resources[static_cast<size_t>(plan.find_resource("average"))].transient) << "the running result is kept";
  EXPECT_TRUE(plan.resources[static_cast<size_t>(plan.find_resource("estimate"))].transient) << "only refining passes read it";
  // What a showing pass writes is kept, even where it changes every frame, so that a display frame
  // can show in steps, each reading what the one before left.
  nlohmann::json softened = graph;
  softened["resources"]["softened"] = image();
  softened["passes"].insert(softened["passes"].begin() + 4, nlohmann::json::object({{"name", "soften"},
                                                                                    {"type", "filter"},
                                                                                    {"params", {{"radius", "frame.index % 2"}}},
                                                                                    {"inputs", {{"source", "viewed"}}},
                                                                                    {"outputs", {{"target", "softened"}}}}));
  softened["passes"][5]["inputs"]["b"] = "softened";
  const Plan in_steps = compile(softened, reuse);
  ASSERT_TRUE(in_steps.refines_apart);
  EXPECT_FALSE(in_steps.resources[static_cast<size_t>(in_steps.find_resource("softened"))].transient);

  // A showing pass that reads this frame's estimate would need it in a showing frame too.
  nlohmann::json shows_estimate = graph;
  shows_estimate["passes"][4]["inputs"]["b"] = "estimate";
  EXPECT_FALSE(compile(shows_estimate, reuse).refines_apart);

  // A history input makes its reader a running result: the writers of what it reads refine with it.
  const Plan averaged = compile(mean_through_history(), reuse);
  EXPECT_TRUE(averaged.refines_apart);
  EXPECT_EQ(refining(averaged), (std::vector<std::string>{"light", "average"}));
}

// A reusable pass's result key follows what it computes from: its parameters and, through what it
// reads, its inputs' writers'; a later pass that rewrites its output makes it follow that pass too
// (the frame leaves that pass's image). A pass that changes every frame has none.
TEST(Compiler, ResultKeysFollowWhatAPassComputesFrom) {
  auto graph = [](double camera_gain, double overlay_gain) {
    return nlohmann::json{
        {"resources", {{"lit", image()}, {"filtered", image()}, {"viewed", image()}, {"out", image()}}},
        {"passes",
         {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
          {{"name", "over"},
           {"type", "overlay"},
           {"params", {{"gain", overlay_gain}}},
           {"outputs", {{"target", "lit"}}},
           {"after", {"light"}}},
          {{"name", "f"}, {"type", "filter"}, {"inputs", {{"source", "lit"}}}, {"outputs", {{"target", "filtered"}}}},
          {{"name", "camera"}, {"type", "source"}, {"params", {{"mode", "b"}, {"gain", camera_gain}}}, {"outputs", {{"color", "viewed"}}}},
          {{"name", "mix"}, {"type", "blend"}, {"inputs", {{"a", "filtered"}, {"b", "viewed"}}}, {"outputs", {{"color", "out"}}}}}},
        {"outputs", {"out"}}};
  };
  CompileOptions reuse;
  reuse.reuse_unchanged_passes = true;
  auto keys = [&](const nlohmann::json& j) {
    std::map<std::string, std::optional<ResultIdentity>> by_name;
    for (const auto& p : compile(j, reuse).passes) by_name[p.name] = p.result_id;
    return by_name;
  };
  const auto before = keys(graph(1.0, 1.0));
  for (const auto& [name, key] : before) EXPECT_TRUE(key.has_value()) << name;
  EXPECT_EQ(keys(graph(1.0, 1.0)), before) << "the same graph, the same keys";
  const auto camera_edit = keys(graph(2.0, 1.0));
  for (const char* same : {"light", "over", "f"}) EXPECT_EQ(camera_edit.at(same), before.at(same)) << same;
  for (const char* changed : {"camera", "mix"}) EXPECT_NE(camera_edit.at(changed), before.at(changed)) << changed;
  const auto overlay_edit = keys(graph(1.0, 2.0));
  for (const char* changed : {"light", "over", "f", "mix"}) EXPECT_NE(overlay_edit.at(changed), before.at(changed)) << changed;
  EXPECT_EQ(overlay_edit.at("camera"), before.at("camera"));
  nlohmann::json every_frame = graph(1.0, 1.0);
  every_frame["passes"][2]["params"] = {{"radius", "frame.index % 2"}};
  EXPECT_FALSE(keys(every_frame).at("f").has_value());
  EXPECT_FALSE(compile(graph(1.0, 1.0)).passes[0].result_id.has_value()) << "a plan that does not reuse passes carries nothing";
}

// A history input ("NAME@previous") reads what NAME held at the end of the last frame: a resource of
// its own, kept with its source out of aliasing, both starting each frame from the layout the last
// one left them in; restarted by what the source's writers depend on, and the frame passed on to
// every reader; the writers of a source that only a history input reads are kept.
TEST(Compiler, HistoryInputsReadTheLastFramesResource) {
  const nlohmann::json graph = mean_through_history();
  const Plan plan = compile(graph);
  const int mean = plan.find_resource("mean"), previous = plan.find_resource("mean@previous");
  ASSERT_GE(mean, 0);
  ASSERT_GE(previous, 0);
  const PlannedResource& history = plan.resources[static_cast<size_t>(previous)];
  const PlannedResource& source = plan.resources[static_cast<size_t>(mean)];
  EXPECT_EQ(history.previous_of, static_cast<uint32_t>(mean));
  EXPECT_FALSE(history.transient);
  EXPECT_FALSE(source.transient) << "the source must outlive the frame";
  EXPECT_TRUE(history.kept_across_frames && source.kept_across_frames);
  EXPECT_TRUE(history.image_usage & VK_IMAGE_USAGE_TRANSFER_DST_BIT);
  EXPECT_TRUE(source.image_usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  EXPECT_EQ(dependency_names(history.history_depends), (std::vector<std::string>{"geometry", "lights", "frame"}));
  for (const auto& p : plan.passes) {
    const std::vector<std::string> expected =
        p.name == "light" ? std::vector<std::string>{"geometry", "lights"} : std::vector<std::string>{"geometry", "lights", "frame"};
    EXPECT_EQ(dependency_names(p.depends), expected) << p.name;
    if (p.name != "average") continue;
    // Both start from where the last frame left them, not from "undefined".
    for (int r : {mean, previous}) {
      auto first = std::find_if(p.barriers.begin(), p.barriers.end(),
                                [&](const PlannedBarrier& b) { return b.resource == static_cast<uint32_t>(r); });
      ASSERT_NE(first, p.barriers.end()) << plan.resources[static_cast<size_t>(r)].name;
      EXPECT_EQ(first->old_layout, plan.resources[static_cast<size_t>(r)].final_state.layout)
          << plan.resources[static_cast<size_t>(r)].name;
      EXPECT_NE(first->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
    }
  }
  const nlohmann::json listed = plan_to_json(plan);
  bool reported = false;
  for (const auto& r : listed["resources"]) {
    if (r["name"] != "mean@previous") continue;
    reported = true;
    EXPECT_EQ(r["previous_of"], "mean");
    EXPECT_EQ(r["restarts_on"], (nlohmann::json{"geometry", "lights"}));
  }
  EXPECT_TRUE(reported);

  // A camera image's history restarts with the camera.
  nlohmann::json camera = graph;
  camera["passes"][0]["params"] = {{"mode", "b"}};
  EXPECT_EQ(dependency_names(compile(camera).resources[static_cast<size_t>(previous)].history_depends),
            (std::vector<std::string>{"camera", "frame"}));

  // Only the next frame reads `kept`: its writer is needed all the same.
  const nlohmann::json only_history = {
      {"resources", {{"lit", image()}, {"kept", image()}, {"out", image()}}},
      {"passes",
       {{{"name", "light"}, {"type", "source"}, {"outputs", {{"color", "lit"}}}},
        {{"name", "keep"}, {"type", "filter"}, {"inputs", {{"source", "lit"}}}, {"outputs", {{"target", "kept"}}}},
        {{"name", "mix"}, {"type", "blend"}, {"inputs", {{"a", "lit"}, {"b", "kept@previous"}}}, {"outputs", {{"color", "out"}}}}}},
      {"outputs", {"out"}}};
  const Plan kept = compile(only_history);
  EXPECT_TRUE(kept.culled.empty());
  EXPECT_EQ(kept.passes.size(), 3u);

  nlohmann::json missing = graph;
  missing["passes"][1]["inputs"]["b"] = "maen@previous";
  EXPECT_NE(compile_error(missing).find(
                "'maen@previous' reads the previous frame's 'maen', which is not a resource of this graph (did you mean 'mean'?)"),
            std::string::npos)
      << compile_error(missing);
  nlohmann::json written = graph;
  written["passes"][1]["outputs"]["color"] = "mean@previous";
  EXPECT_NE(compile_error(written).find("which passes read and do not write"), std::string::npos) << compile_error(written);
  nlohmann::json unwritten = graph;
  unwritten["resources"]["idle"] = image();
  unwritten["passes"][1]["inputs"]["b"] = "idle@previous";
  EXPECT_NE(compile_error(unwritten).find("reads 'idle@previous', the previous frame's 'idle', which no pass writes"), std::string::npos)
      << compile_error(unwritten);
}

namespace {

// graphs/caustics_adaptive.json, compiled against the built-in pass types.
nlohmann::json adaptive_graph() {
  return JsonDocument::load(std::string(CAUSTICA_SOURCE_DIR) + "/graphs/caustics_adaptive.json").root();
}

nlohmann::json& caustic_pass_params(nlohmann::json& graph) {
  for (auto& pass : graph["passes"]) {
    if (pass["type"] == "adaptive_caustic_map") return pass["params"];
  }
  throw std::logic_error("no adaptive_caustic_map pass");
}

Plan compile_builtin(const GraphDesc& desc) {
  CompileOptions options;
  options.scene_values = typical_scene_values();
  options.output_width = 64;
  options.output_height = 32;
  return compile_graph(desc, passes::builtin_registry(), options);
}

nlohmann::json caustic_grid(const Plan& plan) {
  for (const auto& pass : plan.passes) {
    if (pass.type == "adaptive_caustic_map") return pass.params["grid"];
  }
  return nullptr;
}

std::string builtin_compile_error(const nlohmann::json& graph) {
  try {
    compile_builtin(graph_from(graph));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

// The photon grid has one type in every pass type: an integer, a power of two for the traversals
// (each level doubles the 64 x 64 start grid), refused with the nearest where it is not one.
TEST(Compiler, ThePhotonGridIsAnIntegerInEveryCausticPassType) {
  for (const char* type : {"caustic_map", "adaptive_caustic_map", "hierarchical_caustic_map"}) {
    const ParamDecl* grid = passes::builtin_registry().find(type)->find_param("grid");
    ASSERT_NE(grid, nullptr) << type;
    EXPECT_EQ(grid->type, ParamType::int_) << type;
    EXPECT_EQ(grid->power_of_two, std::string(type) != "caustic_map") << type;
  }
  auto g = adaptive_graph();
  caustic_pass_params(g)["grid"] = 1024;
  const Plan plan = compile_builtin(graph_from(g));
  EXPECT_EQ(caustic_grid(plan), 1024);
  EXPECT_TRUE(plan.warnings.empty());

  caustic_pass_params(g)["grid"] = 1000;
  const std::string refused = builtin_compile_error(g);
  EXPECT_TRUE(std::regex_search(refused, std::regex("^test\\.json:[0-9]+:[0-9]+: parameter 'grid' of pass 'caustics#0' is 1000, not a "
                                                    "power of two; the nearest are 512 and 1024 \\(at /passes/[0-9]+/params/grid\\)")))
      << refused;
  caustic_pass_params(g)["grid"] = 131072;
  EXPECT_NE(builtin_compile_error(g).find("is 131072, above its maximum 65536"), std::string::npos);

  // The bundled graph's parameter, set as --set sets it.
  GraphDesc desc = graph_from(adaptive_graph());
  apply_overrides(desc, {"grid=1024"});
  EXPECT_EQ(caustic_grid(compile_builtin(desc)), 1024);
  try {
    apply_overrides(desc, {"grid=3000"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set grid=3000: parameter 'grid' is 3000, not a power of two; the nearest are 2048 and 4096"),
              std::string::npos)
        << e.what();
  }
}

// Files written when the traversals took the grid as a choice of strings read the same, and the
// plan warns with what to write instead.
TEST(Compiler, AGridWrittenAsAStringInAnOldFileStillReads) {
  auto g = adaptive_graph();
  caustic_pass_params(g)["grid"] = "2048";
  Plan plan = compile_builtin(graph_from(g));
  EXPECT_EQ(caustic_grid(plan), 2048);
  ASSERT_EQ(plan.warnings.size(), 1u);
  EXPECT_NE(plan.warnings[0].find("parameter 'grid' of pass 'caustics#0' is the string \"2048\", read as the number 2048; write it without "
                                  "quotes (at /passes/"),
            std::string::npos)
      << plan.warnings[0];

  g = adaptive_graph();
  g["parameters"]["grid"] = {{"type", "choice"},
                             {"default", "2048"},
                             {"while_moving", "512"},
                             {"choices", {"64", "128", "256", "512", "1024", "2048", "4096", "8192", "16384", "32768", "65536"}}};
  GraphDesc old = graph_from(g);
  plan = compile_builtin(old);
  EXPECT_EQ(caustic_grid(plan), 2048);
  ASSERT_EQ(plan.warnings.size(), 1u);
  EXPECT_NE(plan.warnings[0].find("graph parameter 'grid' is a choice of strings, and parameter 'grid' of pass 'caustics#0' "
                                  "(adaptive_caustic_map) takes an integer, so it reads \"2048\" as 2048; declare 'grid' as \"type\": "
                                  "\"int\" with numbers and \"power_of_two\": true (at /parameters/grid)"),
            std::string::npos)
      << plan.warnings[0];
  apply_overrides(old, {"grid=1024"});
  EXPECT_EQ(caustic_grid(compile_builtin(old)), 1024);

  // A choice that is no number stays an error.
  g["parameters"]["grid"] = {{"type", "choice"}, {"default", "fine"}, {"choices", {"fine", "coarse"}}};
  EXPECT_NE(builtin_compile_error(g).find("parameter 'grid' of pass 'caustics#0' expects an integer, got \"fine\" (through graph parameter "
                                          "'grid')"),
            std::string::npos)
      << builtin_compile_error(g);
}

// "power_of_two" is any int parameter's: a graph file's as a pass type's, with the nearest powers
// within the range in its messages.
TEST(Compiler, PowerOfTwoParametersNameTheNearestValues) {
  ParamDecl d{"n", ParamType::int_, 64, 16.0, 256.0, {}, "", false, true};
  EXPECT_EQ(check_param_value(d, 128), "");
  EXPECT_EQ(check_param_value(d, 100), "is 100, not a power of two; the nearest are 64 and 128");
  EXPECT_EQ(check_param_value(d, 17), "is 17, not a power of two; the nearest are 16 and 32");
  EXPECT_EQ(check_param_value(d, 8), "is 8, below its minimum 16");
  d.min = 20.0;
  EXPECT_EQ(check_param_value(d, 24), "is 24, not a power of two; the nearest is 32");
  EXPECT_EQ(powers_of_two_within(d), (std::vector<int64_t>{32, 64, 128, 256}));

  auto g = chain();
  g["parameters"] = {{"side", {{"type", "int"}, {"default", 4}, {"min", 1}, {"max", 16}, {"power_of_two", true}}}};
  g["passes"][3]["params"] = {{"radius", "$side"}};
  GraphDesc desc = graph_from(g);
  EXPECT_TRUE(desc.parameters[0].decl.power_of_two);
  apply_overrides(desc, {"side=8"});
  EXPECT_THROW(apply_overrides(desc, {"side=6"}), InputError);
  g["parameters"]["side"]["default"] = 6;
  EXPECT_NE(compile_error(g).find("the default of parameter 'side' is 6, not a power of two; the nearest are 4 and 8"), std::string::npos);
  g["parameters"]["side"] = {{"type", "int"}, {"default", 4}, {"power_of_two", true}};
  EXPECT_NE(
      compile_error(g).find("parameter 'side' is a power of two, so it needs \"type\": \"int\", a \"min\" of at least 1 and a \"max\""),
      std::string::npos);
}
