// [[tie_row]]: rods placed across the width from a row's positions, height and inset.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "analysis/model/compile_model.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;
const std::filesystem::path kTied = kRoot / "models" / "nishida_b_tied.toml";

TieRowSpec row_of(std::vector<double> x_m, double z_m, int line) {
  TieRowSpec row;
  row.x_m = std::move(x_m);
  row.z_m = z_m;
  row.rod.diameter_m = 0.03;
  row.rod.line = line;
  return row;
}

// Model B tied lists its 12 rods by hand, anchored 5 cm inside the 3.2 m wide walls' outer
// faces (y = +-1.55): two rows give the same anchors, and the same stones hold them.
TEST(TieRows, TwoRowsPlaceModelBTiedsTwelveRods) {
  ModelFile file = read_model_file(kTied);
  const std::vector<TieSpec> by_hand = file.ties;
  ASSERT_EQ(by_hand.size(), 12u);
  file.ties.clear();
  file.tie_rows = {row_of({-10.5, -7.5, -4.5, -1.5, 1.5, 4.5, 7.5, 10.5}, 5.44, 40), row_of({-10.5, -7.5, 7.5, 10.5}, 3.52, 44)};
  const ModelOptions options;
  const CompiledModel rows = compile_model(file, kTied, options);
  ASSERT_EQ(rows.ties.size(), 12u);
  const Model hand = load_model(read_model_file(kTied), kTied, options);
  for (std::size_t t = 0; t < by_hand.size(); ++t) {
    EXPECT_LT((rows.ties[t].from - by_hand[t].from).norm(), 1e-12) << t;
    EXPECT_LT((rows.ties[t].to - by_hand[t].to).norm(), 1e-12) << t;
    EXPECT_EQ(rows.ties[t].line, t < 8 ? 40 : 44);
    EXPECT_EQ(rows.model.ties[t].block_a, hand.ties[t].block_a) << t;
    EXPECT_EQ(rows.model.ties[t].block_b, hand.ties[t].block_b) << t;
    EXPECT_NEAR(rows.model.ties[t].rest_length_m, 3.1, 1e-12) << t;
  }
}

std::string error_of(const TieRowSpec& row) {
  const std::vector<BridgeBlock> blocks = generate_bridge(read_model_file(kTied).bridge);
  try {
    tie_row_rods(row, blocks, kTied);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A row above the bridge, one beyond its ends, and an inset that leaves no rod are each
// refused at the row's line, naming the rod.
TEST(TieRows, ARodWithNoMasonryToCrossIsRefusedAtItsRowsLine) {
  EXPECT_THAT(error_of(row_of({0}, 9, 7)),
              HasSubstr("nishida_b_tied.toml:7: [[tie_row]] rod at x = 0 m, z = 9 m: its line across the width meets no free stone"));
  EXPECT_THAT(error_of(row_of({1.5, 30}, 5.44, 8)), HasSubstr(":8: [[tie_row]] rod at x = 30 m, z = 5.44 m: its line"));
  TieRowSpec wide = row_of({1.5}, 5.44, 9);
  wide.inset_m = 1.6;
  EXPECT_THAT(error_of(wide), HasSubstr(":9: [[tie_row]] rod at x = 1.5 m, z = 5.44 m: the masonry it crosses is 3.2 m wide, "
                                        "not more than two insets (inset_m = 1.6)"));
  EXPECT_EQ(error_of(row_of({1.5}, 5.44, 9)), "");
}

// A row along a course joint (the bed of the wall stone that holds an anchor over an abutment) runs
// between two stones: its anchors lie on their faces, which compile_model refuses at the
// row's line.
TEST(TieRows, ARowOnACourseJointIsRefusedAtItsLine) {
  ModelFile file = read_model_file(kTied);
  double bed_z = 0;
  for (const BridgeBlock& b : generate_bridge(file.bridge)) {
    Vec3 lo = b.shape.vertices[0], hi = lo;
    for (const Vec3& v : b.shape.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    if (b.part == Part::wall && lo.x() < -10.5 && hi.x() > -10.5 && lo.y() < -1.55 && hi.y() > -1.55 && lo.z() < 3.52 && hi.z() > 3.52)
      bed_z = lo.z();
  }
  ASSERT_GT(bed_z, 2.5);
  file.ties.clear();
  file.tie_rows = {row_of({-10.5}, bed_z, 12)};
  try {
    compile_model(file, kTied, ModelOptions{});
    FAIL() << "a rod on a joint was built";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nishida_b_tied.toml:12: tie 0: its anchor at (-10.5, -1.55, "));
    EXPECT_THAT(e.what(), HasSubstr(" lies on a face of"));
  }
}

}  // namespace
}  // namespace ishibashi
