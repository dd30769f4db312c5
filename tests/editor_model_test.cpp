// The editor's graph model on the CPU: every operation and its undo on every bundled graph, text
// that keeps the author's bytes, saves, and a script of operations that rebuilds one bundled graph
// from another.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "builtin_passes.h"
#include "graph/compiler.h"
#include "io/json_document.h"
#include "model/graph_model.h"
#include "model/json_text.h"

using namespace caustica;
using editor::GraphModel;
using nlohmann::ordered_json;

namespace {

const graph::PassRegistry& registry() {
  return passes::builtin_registry();
}

std::filesystem::path graphs_dir() {
  return std::filesystem::path(CAUSTICA_SOURCE_DIR) / "graphs";
}

std::vector<std::filesystem::path> bundled_graphs() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(graphs_dir())) {
    if (e.path().extension() == ".json" && e.path().filename() != "schema.json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string file_text(const std::filesystem::path& path) {
  return read_text_file(path.string(), 1 << 24);
}

std::string plan_of(const graph::GraphDesc& desc) {
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  nlohmann::json plan = graph::plan_to_json(graph::compile_graph(desc, registry(), options));
  plan.erase("file");
  return plan.dump(1);
}

// A value of the parameter other than `current`, within its declared range.
nlohmann::json other_value(const graph::ParamDecl& d, const nlohmann::json& current) {
  switch (d.type) {
    case graph::ParamType::bool_: return !current.get<bool>();
    case graph::ParamType::choice:
      for (const auto& c : d.choices) {
        if (c != current) return c;
      }
      return current;
    case graph::ParamType::int_: {
      const double v = current.get<double>();
      return static_cast<int64_t>(v + 1 <= d.max.value_or(1e9) ? v + 1 : v - 1);
    }
    case graph::ParamType::float_: {
      const double v = current.get<double>();
      return v + 0.5 <= d.max.value_or(1e9) ? v + 0.5 : v - 0.5;
    }
  }
  return current;
}

// Every edit, and every refusal, leaves a model whose text is a valid graph; undo gives back the
// text before the edit byte for byte, and redo the text after it.
// Returns whether the edit was applied.
template <class Edit>
bool check_edit_and_undo(GraphModel& model, const std::string& what, Edit&& edit) {
  SCOPED_TRACE(what);
  const std::string before = model.text();
  bool applied = false;
  try {
    edit();
    applied = model.text() != before;
  } catch (const InputError& e) {
    EXPECT_EQ(model.text(), before) << "a refused edit changed the graph: " << e.what();
    EXPECT_FALSE(std::string(e.what()).empty());
    if (std::getenv("SHOW_REFUSALS")) std::printf("  refused %s: %s\n", what.c_str(), e.what());
    return false;
  }
  if (!applied) return false;
  const std::string after = model.text();
  EXPECT_NO_THROW(graph::load_graph(JsonDocument::parse(after, "edited.json")));
  EXPECT_TRUE(model.undo());
  EXPECT_EQ(model.text(), before);
  EXPECT_TRUE(model.redo());
  EXPECT_EQ(model.text(), after);
  EXPECT_TRUE(model.undo());
  return true;
}

}  // namespace

TEST(JsonText, UnchangedValuesKeepTheirBytes) {
  for (const auto& path : bundled_graphs()) {
    const std::string text = file_text(path);
    EXPECT_EQ(editor::write_preserving(ordered_json::parse(text), text), text) << path;
  }
  const std::string odd = "  {\"b\" :1,\"a\":[ 1,2 ,3],\n\t\"c\": {\"x\": 1.50}}  \n";
  EXPECT_EQ(editor::write_preserving(ordered_json::parse(odd), odd), odd);
}

TEST(JsonText, AnEditChangesOnlyWhatWasEdited) {
  const std::string text = file_text(graphs_dir() / "core_demo.json");
  ordered_json value = ordered_json::parse(text);
  value["passes"][1]["params"]["radius"] = 5;
  std::string expected = text;
  const std::string from = R"("params": {"radius": "$blur_radius", "axis": "x"})";
  ASSERT_NE(expected.find(from), std::string::npos);
  expected.replace(expected.find(from), from.size(), R"("params": {"radius": 5, "axis": "x"})");
  EXPECT_EQ(editor::write_preserving(value, text), expected);

  // A removed member takes its separator with it; an added one copies its neighbours' spacing.
  value = ordered_json::parse(text);
  value["resources"].erase("preview");
  value["resources"]["extra"] = {{"type", "image"}, {"format", "rgba8"}};
  const std::string written = editor::write_preserving(value, text);
  EXPECT_EQ(ordered_json::parse(written), value);
  EXPECT_EQ(written.find("preview\": {"), std::string::npos);
  EXPECT_NE(written.find(",\n    \"extra\": {"), std::string::npos) << written;
  // Everything after the resources is the original's text.
  const std::string tail = text.substr(text.find("  \"passes\""));
  EXPECT_EQ(written.substr(written.size() - tail.size()), tail);
}

TEST(JsonText, AnyEditReadsBackAsTheEditedValue) {
  // Random edits of every kind to every bundled graph: what is written parses to the value.
  std::mt19937 random(7);
  for (const auto& path : bundled_graphs()) {
    const std::string text = file_text(path);
    for (int round = 0; round < 20; ++round) {
      ordered_json value = ordered_json::parse(text);
      auto& passes = value["passes"];
      const size_t i = random() % passes.size();
      switch (round % 5) {
        case 0: passes.erase(passes.begin() + static_cast<long>(i)); break;
        case 1: passes.push_back({{"name", "new"}, {"type", "tonemap"}}); break;
        case 2: passes[i]["params"]["x"] = {1, 2, {{"deep", "er"}}}; break;
        case 3: passes[i].erase("name"); break;
        case 4: value["resources"] = ordered_json::object(); break;
      }
      EXPECT_EQ(ordered_json::parse(editor::write_preserving(value, text)), value) << path << " round " << round;
    }
  }
}

TEST(GraphModel, EveryBundledGraphRoundTripsByteForByte) {
  for (const auto& path : bundled_graphs()) {
    GraphModel model = GraphModel::open(path.string(), registry());
    EXPECT_EQ(model.text(), file_text(path)) << path;
    EXPECT_FALSE(model.modified());
    EXPECT_FALSE(model.can_undo());
  }
}

TEST(GraphModel, EveryOperationAndItsUndoOnEveryBundledGraph) {
  for (const auto& path : bundled_graphs()) {
    SCOPED_TRACE(path.filename().string());
    GraphModel model = GraphModel::open(path.string(), registry());
    const std::string original = model.text();
    const ordered_json doc = model.json();
    int applied = 0, tried = 0;
    auto count = [&](bool done) {
      applied += done ? 1 : 0;
      ++tried;
    };
    for (const auto& pass : doc["passes"]) {
      const std::string name = pass["name"];
      const graph::PassTypeDecl& decl = *registry().find(pass["type"].get<std::string>());
      // Always possible: a new name, a place on the canvas.
      EXPECT_TRUE(check_edit_and_undo(model, "rename " + name, [&] { model.rename_pass(name, name + "_renamed"); }));
      EXPECT_TRUE(check_edit_and_undo(model, "move " + name, [&] { model.set_position(name, 10, 20); }));
      count(check_edit_and_undo(model, "remove " + name, [&] { model.remove_pass(name); }));
      count(check_edit_and_undo(model, "disable " + name, [&] { model.set_enabled(name, false); }));
      for (const auto& param : decl.params) {
        const nlohmann::json current =
            pass.contains("params") && pass["params"].contains(param.name) &&
                    !(pass["params"][param.name].is_string() && pass["params"][param.name].get<std::string>()[0] == '$')
                ? nlohmann::json::parse(pass["params"][param.name].dump())
                : param.default_value;
        count(check_edit_and_undo(model, "set " + name + "." + param.name,
                                  [&] { model.set_param(name, param.name, other_value(param, current)); }));
        count(check_edit_and_undo(model, "reset " + name + "." + param.name, [&] { model.reset_param(name, param.name); }));
      }
      for (const char* section : {"inputs", "outputs"}) {
        if (!pass.contains(section)) continue;
        for (const auto& [port, resource] : pass[section].items()) {
          count(check_edit_and_undo(model, "disconnect " + name + "." + port, [&] { model.disconnect(name, port); }));
        }
      }
    }
    for (const auto& [resource, description] : doc["resources"].items()) {
      EXPECT_TRUE(check_edit_and_undo(model, "rename resource " + resource, [&] { model.rename_resource(resource, resource + "_2"); }));
      count(check_edit_and_undo(model, "remove resource " + resource, [&] { model.remove_resource(resource); }));
    }
    for (const auto& type : registry().names()) {
      count(check_edit_and_undo(model, "add " + type, [&] { model.add_pass(type); }));
    }
    EXPECT_EQ(model.text(), original);
    // Most edits are valid ones; the refusals are the compiler's to make.
    EXPECT_GT(applied, tried / 3) << applied << " of " << tried << " applied";
    std::printf("%s: %d of %d edits applied, the rest refused\n", path.filename().c_str(), applied, tried);
  }
}

TEST(GraphModel, InvalidEditsAreRefusedWithTheValidatorsMessage) {
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  const std::string before = model.text();
  auto refused = [&](auto&& edit, const std::string& message) {
    try {
      edit();
      ADD_FAILURE() << "not refused; expected '" << message << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
    EXPECT_EQ(model.text(), before);
    EXPECT_FALSE(model.can_undo());
  };
  refused([&] { model.set_param("blur_x", "radius", 1000); }, "parameter 'radius' of pass 'blur_x'");
  refused([&] { model.set_param("blur_x", "radius", "$nothing"); }, "no graph parameter 'nothing'");
  refused([&] { model.set_param("blur_x", "radus", 1); }, "did you mean 'radius'");
  refused([&] { model.connect("tonemap", "source", "ldr"); }, "ldr");
  refused([&] { model.connect("tonemap", "source", "missing"); }, "no resource named 'missing'");
  refused([&] { model.connect("blur_x", "nope", "hdr"); }, "has no port 'nope'");
  refused([&] { model.disconnect("tonemap", "source"); }, "is not connected");
  refused([&] { model.remove_pass("blur_x"); }, "which no pass writes");
  refused([&] { model.rename_pass("blur_x", "blur_y"); }, "already exists");
  refused([&] { model.rename_pass("blur_x", "bad name!"); }, "pass name");
  refused([&] { model.add_pass("no_such_type"); }, "unknown pass type");
  refused([&] { model.remove_pass("nobody"); }, "no pass named 'nobody'");
  refused([&] { model.set_outputs({"nothing"}); }, "nothing");
  refused([&] { model.set_resource_field("hdr", "format", "rgba9"); }, "unknown format 'rgba9'");
  refused([&] { model.add_pass("lighting"); }, "cannot add a lighting pass");
}

TEST(GraphModel, AddPassFillsPortsAndDefaultsAndRemovePassTakesItsResources) {
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  const std::string original = model.text();
  const std::string name = model.add_pass("box_blur");
  EXPECT_EQ(name, "box_blur");
  const ordered_json& pass = model.json()["passes"].back();
  // Every declared parameter at its default; the input bound to an image a pass writes, the
  // latest writer first (tonemap writes rgba8, which a blur does not take; unused_preview's is).
  for (const auto& p : registry().find("box_blur")->params)
    EXPECT_EQ(nlohmann::json::parse(pass["params"][p.name].dump()), p.default_value);
  EXPECT_EQ(pass["inputs"]["source"], "preview");
  EXPECT_EQ(pass["outputs"]["target"], "box_blur_target");
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["format"], "rgba16f");
  // Its output has the size of its input (one extent group): a quarter of the frame.
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["width"], "output.width / 4");
  // Re-wired to a full-size image, the output it made follows (else the pass could not go live).
  model.connect("box_blur", "source", "hdr");
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["width"], "output.width");
  model.connect("tonemap", "source", "box_blur_target");
  EXPECT_EQ(model.desc().passes.back().name, "box_blur");
  model.undo();
  model.undo();
  EXPECT_EQ(model.add_pass("box_blur"), "box_blur_2");
  model.remove_pass("box_blur_2");
  model.remove_pass("box_blur");
  EXPECT_FALSE(model.json()["resources"].contains("box_blur_target"));
  EXPECT_EQ(model.text(), original);
  EXPECT_FALSE(model.modified());
  EXPECT_EQ(model.undo_label(), "remove pass box_blur");
}

TEST(GraphModel, SavesOnlyWhatChangedAndNeverOverAnotherEditorsChange) {
  const auto dir = std::filesystem::temp_directory_path() / ("caustica_model_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "g.json";
  std::filesystem::copy_file(graphs_dir() / "caustics_adaptive.json", path, std::filesystem::copy_options::overwrite_existing);
  const std::string original = file_text(path);
  GraphModel model = GraphModel::open(path.string(), registry());
  model.save();
  EXPECT_EQ(file_text(path), original);

  model.set_param("tonemap", "exposure", 2.5);
  EXPECT_TRUE(model.modified());
  model.save();
  EXPECT_FALSE(model.modified());
  std::string expected = original;
  const std::string from = "\"exposure\": \"$exposure\"";
  ASSERT_NE(expected.find(from), std::string::npos);
  expected.replace(expected.find(from), from.size(), "\"exposure\": 2.5");
  EXPECT_EQ(file_text(path), expected);

  // Another editor writes the file: a save is refused until the user says to overwrite.
  { std::ofstream(path) << original; }
  EXPECT_TRUE(model.changed_on_disk());
  model.set_param("tonemap", "exposure", 3.0);
  EXPECT_THROW(model.save(), InputError);
  EXPECT_EQ(file_text(path), original);
  model.save(true);
  EXPECT_EQ(ordered_json::parse(file_text(path))["passes"].back()["params"]["exposure"], 3.0);
  // No temporary file is left beside it.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
  std::filesystem::remove_all(dir);
}

TEST(GraphModel, MalformedFilesAreMessagesNotCrashes) {
  for (const char* text : {"", "{", "{\"passes\": 3}", "[1, 2]", "{\"a\": 1, \"a\": 2}", "\"just a string\""}) {
    EXPECT_THROW(GraphModel(text, "bad.json", registry()), InputError) << text;
  }
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/bad_graphs")) {
    if (entry.path().extension() != ".json") continue;
    try {
      GraphModel::open(entry.path().string(), registry());
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(entry.path().filename().string()), std::string::npos) << e.what();
    }
  }
}

// caustics_adaptive.json rebuilt from core_demo.json by the model's operations alone, in the order a
// person would use them in the editor; the compiled plans are the same.
TEST(GraphModel, AnEditScriptRebuildsCausticsAdaptiveFromCoreDemo) {
  const ordered_json target = ordered_json::parse(file_text(graphs_dir() / "caustics_adaptive.json"));
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  model.set_graph_field("name", target["name"]);
  model.set_graph_field("description", target["description"]);
  for (const auto& [name, declaration] : target["parameters"].items()) {
    if (!model.json()["parameters"].contains(name)) {
      model.add_parameter(name, declaration);
      continue;
    }
    for (const auto& [field, value] : declaration.items()) model.set_parameter_field(name, field, value);
  }
  for (const auto& [name, description] : target["resources"].items()) {
    if (!model.json()["resources"].contains(name)) model.add_resource(name, description);
  }
  std::set<std::string> kept;
  for (const auto& pass : target["passes"]) {
    const std::string name = pass["name"];
    kept.insert(name);
    bool exists = false;
    for (const auto& p : model.json()["passes"]) exists = exists || p["name"] == name;
    std::vector<std::string> made;  // resources add_pass made for the outputs, replaced below
    if (!exists) {
      ASSERT_EQ(model.add_pass(pass["type"], name), name);
      const ordered_json outputs = model.json()["passes"].back().value("outputs", ordered_json::object());
      for (const auto& [port, resource] : outputs.items()) made.push_back(resource);
    }
    for (const char* section : {"inputs", "outputs"}) {
      const ordered_json bindings = pass.value(section, ordered_json::object());
      for (const auto& [port, resource] : bindings.items()) model.connect(name, port, resource);
    }
    for (const auto& r : made) {
      if (!target["resources"].contains(r)) model.remove_resource(r);
    }
    const ordered_json params = pass.value("params", ordered_json::object());
    for (const auto& [param, value] : params.items()) model.set_param(name, param, value);
    if (pass.contains("enabled")) model.set_enabled(name, pass["enabled"]);
  }
  model.set_outputs(target["outputs"]);
  // Readers before writers, as a person would unpick a chain.
  const ordered_json passes_now = model.json()["passes"];
  for (auto pass = passes_now.rbegin(); pass != passes_now.rend(); ++pass) {
    if (!kept.count((*pass)["name"])) model.remove_pass((*pass)["name"]);
  }
  const ordered_json parameters_now = model.json()["parameters"];
  for (const auto& [name, declaration] : parameters_now.items()) {
    if (!target["parameters"].contains(name)) model.remove_parameter(name);
  }
  const ordered_json resources_now = model.json()["resources"];
  for (const auto& [name, description] : resources_now.items()) {
    if (!target["resources"].contains(name)) model.remove_resource(name);
  }
  EXPECT_EQ(plan_of(model.desc()), plan_of(graph::load_graph_file((graphs_dir() / "caustics_adaptive.json").string())));
  // And every step can be undone, back to core_demo.json as it is on disk.
  while (model.undo()) {
  }
  EXPECT_EQ(model.text(), file_text(graphs_dir() / "core_demo.json"));
}
