// caustica edit's recovery copy (editor/model/recovery_copy.h): the unsaved graph written beside
// its file when a session ends on a device failure, and offered at the next open.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "builtin_passes.h"
#include "io/files.h"
#include "model/recovery_copy.h"

namespace caustica::editor {
namespace {

std::string recovered_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A scratch copy of the default graph (graphs/caustics_adaptive.json), removed with its recovery copy at the end.
class RecoveryCopy : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("caustica_recovery_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                                  "_" + std::to_string(reinterpret_cast<uintptr_t>(this)));
    std::filesystem::create_directories(dir_);
    graph_ = (dir_ / "mine.json").string();
    std::filesystem::copy_file(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "graphs" / "caustics_adaptive.json", graph_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  std::string graph_;
};

TEST_F(RecoveryCopy, IsBesideTheGraphFile) {
  EXPECT_EQ(recovery_path("graphs/mine.json"), "graphs/mine.recovered.json");
  EXPECT_EQ(recovery_path("mine"), "mine.recovered.json");
}

TEST_F(RecoveryCopy, HoldsTheUnsavedGraphAndIsOfferedAtTheNextOpen) {
  GraphModel model = GraphModel::open(graph_, passes::builtin_registry());
  EXPECT_EQ(recovery_offer(graph_), "");
  const std::string pass = model.desc().passes.front().name;
  model.set_position(pass, 123, 45);
  ASSERT_TRUE(model.modified());
  const std::string written = write_recovery_copy(model);
  EXPECT_EQ(written, recovery_path(graph_));
  EXPECT_EQ(recovered_text(written), model.text());
  EXPECT_NE(recovered_text(graph_), model.text()) << "the graph file itself is left as saved";
  const std::string offer = recovery_offer(graph_);
  EXPECT_NE(offer.find(written), std::string::npos) << offer;
  EXPECT_NE(offer.find("mv " + written + " " + graph_), std::string::npos) << offer;
}

TEST_F(RecoveryCopy, NothingUnsavedWritesNothing) {
  GraphModel model = GraphModel::open(graph_, passes::builtin_registry());
  EXPECT_EQ(write_recovery_copy(model), "");
  EXPECT_FALSE(std::filesystem::exists(recovery_path(graph_)));
}

}  // namespace
}  // namespace caustica::editor
