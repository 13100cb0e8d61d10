// The table of plugin kinds (framework/plugins/kinds.hpp): one row per kind of the SDK, read by
// the pipeline's reserved keys and the crash handler's roles.
#include <gtest/gtest.h>

#include <set>

#include "plugins/kinds.hpp"

using gdsmc::PluginKind;
using namespace gdsmc::host;

TEST(PluginKinds, EveryKindOfTheSdkHasOneRow) {
  std::set<std::string> names, roles, entries;
  for (std::uint32_t k = 1; k <= 5; ++k) {  // the SDK's PluginKind values
    const PluginKindInfo* row = find_kind(static_cast<PluginKind>(k));
    ASSERT_NE(row, nullptr) << "kind " << k;
    names.insert(gdsmc::to_string(row->kind)), roles.insert(row->role), entries.insert(row->first_entry);
  }
  EXPECT_EQ(kPluginKinds.size(), 5u);
  EXPECT_EQ(names.size(), 5u);
  EXPECT_EQ(roles.size(), 5u);
  EXPECT_EQ(entries.size(), 5u);
  EXPECT_EQ(find_kind(static_cast<PluginKind>(6)), nullptr);
  EXPECT_THROW(kind_info(static_cast<PluginKind>(6)), std::logic_error);
}

TEST(PluginKinds, OnlyAKindThatWritesOutputReservesTheSamplingKeys) {
  for (const PluginKindInfo& row : kPluginKinds) {
    const auto& keys = reserved_keys(row.kind);
    const bool sampling = std::find(keys.begin(), keys.end(), "sample_every") != keys.end();
    EXPECT_EQ(sampling, row.writes_output) << gdsmc::to_string(row.kind);
    EXPECT_NE(std::find(keys.begin(), keys.end(), "plugin"), keys.end()) << gdsmc::to_string(row.kind);
  }
  EXPECT_EQ(all_reserved_keys().size(), 4u);
}
