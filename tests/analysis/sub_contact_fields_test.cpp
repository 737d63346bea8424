// The sub-contact arrays are listed once (ISHIBASHI_SUB_CONTACT_FIELDS in engine/state.h)
// and resize, copy_range (the narrowphase's regroup) and the checkpoint are made from that
// list: every field, filled with values unique to it, survives a regroup and a checkpoint
// round trip, and the struct holds no array outside the list.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "analysis/run/checkpoint.h"
#include "engine/state.h"

namespace ishibashi {
namespace {

constexpr int kListed = 0
#define ISHIBASHI_COUNT_FIELD(type, name, comment) +1
    ISHIBASHI_SUB_CONTACT_FIELDS(ISHIBASHI_COUNT_FIELD)
#undef ISHIBASHI_COUNT_FIELD
    ;
// An array added to SubContacts but not to the list would be missed by every derived
// operation: the struct must be exactly its listed arrays.
static_assert(sizeof(SubContacts) == kListed * sizeof(std::vector<double>), "a SubContacts array is not in the list");

// Value k of field f: distinct across fields and elements, of the field's own type.
template <class T>
T value(int field, int k) {
  const int v = 1000 * (field + 1) + k;
  if constexpr (std::is_same_v<T, Vec3>) return Vec3(v, v + 0.25, v + 0.5);
  else if constexpr (std::is_same_v<T, std::uint8_t>) return static_cast<std::uint8_t>(v * 7 + field);
  else return static_cast<T>(v);
}

void fill(SubContacts& c, int offset) {
  int field = 0;
  c.for_each_array([&](auto& array) {
    using T = typename std::decay_t<decltype(array)>::value_type;
    for (std::size_t k = 0; k < array.size(); ++k) array[k] = value<T>(field, offset + static_cast<int>(k));
    ++field;
  });
}

// Every field of b[i] equals a[j], named on failure.
void expect_same(const SubContacts& a, std::size_t j, const SubContacts& b, std::size_t i, const std::string& what) {
  std::vector<std::string> names;
  a.for_each_named_array([&](const char* name, const auto&) { names.emplace_back(name); });
  const auto collect = [&](const SubContacts& c, std::size_t k, std::vector<std::string>& bytes) {
    c.for_each_array([&](const auto& array) {
      bytes.emplace_back(reinterpret_cast<const char*>(&array[k]), sizeof(array[k]));
    });
  };
  std::vector<std::string> left, right;
  collect(a, j, left);
  collect(b, i, right);
  ASSERT_EQ(left.size(), names.size());
  for (std::size_t f = 0; f < names.size(); ++f) EXPECT_EQ(left[f], right[f]) << what << ": field " << names[f];
}

TEST(SubContactFields, EveryFieldSurvivesARegroupCopy) {
  SubContacts src, dst;
  src.resize(5);
  fill(src, 0);
  dst.resize(8);
  fill(dst, 100);
  dst.copy_range(src, 1, 3, 4);  // src[1..3] -> dst[4..6]
  for (int k = 0; k < 3; ++k) expect_same(src, 1 + k, dst, 4 + k, "copied");
  SubContacts untouched;
  untouched.resize(8);
  fill(untouched, 100);
  for (int k : {0, 1, 2, 3, 7}) expect_same(untouched, k, dst, k, "outside the copied range");
}

TEST(SubContactFields, EveryFieldSurvivesACheckpoint) {
  State before;
  before.contacts.resize(6);
  fill(before.contacts, 7);
  std::stringstream file;
  CheckpointWriter out(file);
  write_state(out, before);
  State after;
  CheckpointReader in(file);
  read_state(in, after);
  ASSERT_EQ(after.contacts.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) expect_same(before.contacts, k, after.contacts, k, "after a checkpoint");
}

}  // namespace
}  // namespace ishibashi
