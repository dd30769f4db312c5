// The stability suite (docs/stability.md): `caustica bench stability` run small, with validation,
// and what must hold in every case for every caustic method checked on its CSV. The cases: the
// ball lens; the bunny with its light moving; n = 2.4; grazing light; a torus; stacked refractors;
// a refractor smaller than the adaptive start grid's spacing; one filling the light's view; the
// light close to the refractor; n = 1; no refractor.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Row {
  std::string case_name, method;
  std::map<std::string, double> values;
  double operator[](const std::string& column) const { return values.at(column); }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

struct StabilityRun {
  int exit_code = -1;
  std::vector<Row> rows;

  std::vector<Row> of_case(const std::string& name) const {
    std::vector<Row> found;
    for (const auto& r : rows) {
      if (r.case_name == name) found.push_back(r);
    }
    return found;
  }
};

// Runs the bench once, small, with validation; its CSV holds every case x method.
StabilityRun run_stability() {
  StabilityRun run;
  const fs::path dir = fs::temp_directory_path() / ("caustica_stability_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string command = "'" CAUSTICA_BIN "' bench stability --grid 512 --caustic-size 256 --reference-photons 4e6 --frames 1 --validate --out '" +
                              dir.string() + "'";
  run.exit_code = std::system(command.c_str());
  std::ifstream csv(dir / "stability.csv");
  std::string header;
  std::getline(csv, header);
  const auto columns = split(header);
  for (std::string line; std::getline(csv, line);) {
    const auto cells = split(line);
    Row row{cells.at(0), cells.at(1), {}};
    for (size_t i = 2; i < cells.size() && i < columns.size(); ++i) row.values[columns[i]] = std::stod(cells[i]);
    run.rows.push_back(row);
  }
  fs::remove_all(dir);
  return run;
}

bool seeded(const Row& r) { return r.method.find("unseeded") == std::string::npos; }

}  // namespace

TEST(Stability, EveryMethodHoldsInEveryCase) {
  const StabilityRun run = run_stability();
  {
    SCOPED_TRACE("EveryCaseRanEveryMethodWithoutAValidationMessage");
    EXPECT_EQ(run.exit_code, 0) << "bench stability failed or saw validation messages";
    EXPECT_EQ(run.rows.size(), 11u * 6u);  // cases x (five methods and the unseeded hybrid)
  }
  {
    SCOPED_TRACE("NoNanOrInfAnywhere");
    for (const auto& r : run.rows) EXPECT_EQ(r["nonfinite"], 0.0) << r.case_name << ", " << r.method;
  }
  // A method may lose energy, never create it. The reference is itself a sample: its landed flux
  // is uncertain by about 1 / sqrt(photons landed), allowed three times over, plus 1% for the
  // engine's grid sampling of the silhouette.
  {
    SCOPED_TRACE("NoMethodCreatesEnergy");
    for (const auto& r : run.rows) {
      const double landed = r["reference_landed_photons"];
      const double tolerance = 0.01 + (landed > 0 ? 3.0 / std::sqrt(landed) : 0.0);
      EXPECT_LE(r["energy_ratio"], 1.0 + tolerance) << r.case_name << ", " << r.method;
    }
  }
  // Moving the light by 1e-4 moves the caustic by a fraction of a texel: the map may change by a
  // little, never jump.
  {
    SCOPED_TRACE("StableUnderATinyLightMove");
    for (const auto& r : run.rows) {
      EXPECT_LT(r["shift_l1"], 0.05) << r.case_name << ", " << r.method;
      EXPECT_NEAR(r["shift_energy"], 1.0, 0.01) << r.case_name << ", " << r.method;
    }
  }
  // Along a light path the caustic may change from step to step no more than the reference's own
  // (which also carries the reference's sampling noise), with a quarter to spare, for the methods
  // that splat into the multi-resolution map. The regular map splats every photon into one texel:
  // its speckle flickers more (0.083 against the reference's 0.062 when this was written), which
  // docs/stability.md reports as one of its failures rather than a must-hold.
  {
    SCOPED_TRACE("FlickersNoMoreThanTheReference");
    const auto rows = run.of_case("bunny with the light moving");
    ASSERT_FALSE(rows.empty());
    for (const auto& r : rows) {
      EXPECT_GT(r["flicker"], 0.0) << r.method << ": the light moved, so the caustic must";
      if (r.method != "regular") {
        EXPECT_LE(r["flicker"], 1.25 * r["reference_flicker"]) << r.method;
      }
    }
  }
  // Coverage seeding finds a refractor that falls between the start grid's photons; the paper's
  // traversal, which drops a cluster when its four photons miss, loses all of it.
  {
    SCOPED_TRACE("SeededTraversalsFindTheTinyRefractor");
    const auto rows = run.of_case("tiny refractor");
    ASSERT_EQ(rows.size(), 6u);
    for (const auto& r : rows) {
      if (seeded(r)) EXPECT_GT(r["energy_ratio"], 0.5) << r.method;
      else EXPECT_EQ(r["energy_ratio"], 0.0) << r.method << ": the case no longer exercises the unseeded failure";
    }
  }
  // n = 1: every method puts the light exactly where it would have gone without the sphere.
  {
    SCOPED_TRACE("IndexOneMatchesTheReference");
    for (const auto& r : run.of_case("n = 1")) {
      if (!seeded(r)) continue;
      EXPECT_NEAR(r["energy_ratio"], 1.0, 0.02) << r.method;
      EXPECT_LT(r["shape_l1"], 0.06) << r.method;
    }
  }
  {
    SCOPED_TRACE("NoRefractorNoCausticNoPhotons");
    const auto rows = run.of_case("no refractor");
    ASSERT_EQ(rows.size(), 6u);
    for (const auto& r : rows) {
      EXPECT_EQ(r["photons_processed"], 0.0) << r.method;
      EXPECT_EQ(r["relative_l1"], 0.0) << r.method;
    }
  }
}
