// How core names options in its messages, and how an edge spells them.
#include <gtest/gtest.h>

#include "common/option_names.h"

namespace mpumesh {
namespace {

TEST(OptionNames, EachBackquotedNameIsSpelledByTheEdge) {
  const auto shout = [](std::string_view n) { return "<" + std::string(n) + ">"; };
  EXPECT_EQ(option_ref("keep_specks"), "`keep_specks`");
  EXPECT_EQ(spell_options("use " + option_ref("min_volume") + " or " + option_ref("largest") + ".", shout),
            "use <min_volume> or <largest>.");
  EXPECT_EQ(spell_options("`a1` `b_2`", shout), "<a1> <b_2>");
  // Only lower-case names with digits and underscores are names; the rest stays.
  for (const char* kept : {"", "plain text", "`Upper`", "`two words`", "an open ` quote", "``", "`x-y`", "end `"})
    EXPECT_EQ(spell_options(kept, shout), kept) << kept;
  EXPECT_EQ(spell_options("`` `n` ` `", shout), "`` <n> ` `");
}

}  // namespace
}  // namespace mpumesh
