// Core names the options in its messages by stable names (core/common/option_names.h);
// the command line spells them as its flags (tools/option_spelling.h) and the Python
// module as its keywords (tests/python/test_module.py): the spellings, and one message of
// each kind, an option's check and a run's failure, as the command line prints it.
#include <gtest/gtest.h>

#include "cli_support.h"
#include "common/option_names.h"
#include "option_spelling.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(OptionSpelling, TheCommandLineSpellsItsFlagsAndPythonItsKeywords) {
  EXPECT_EQ(tools::cli_flag("particles", "run"), "--particles");
  EXPECT_EQ(tools::cli_flag("keep_specks", "run"), "--keep-specks");
  EXPECT_EQ(tools::cli_flag("particle_spacing", "run"), "--spacing");
  EXPECT_EQ(tools::cli_flag("particle_iterations", "run"), "--particle-iterations");
  EXPECT_EQ(tools::cli_flag("particle_iterations", "sample"), "--iterations");
  EXPECT_EQ(tools::cli_flag("volume_size", "tetmesh"), "--size");
  EXPECT_EQ(tools::cli_flag("volume_size", "run"), "--volume-size");
  EXPECT_EQ(tools::cli_text("ask for fewer `particles` (0: from `particle_spacing`)", "run"),
            "ask for fewer --particles (0: from --spacing)");
  EXPECT_EQ(spell_options("ask for fewer `particles` (0: from `particle_spacing`)", tools::python_spelling()),
            "ask for fewer particles= (0: from particle_spacing=)");
  // Text that names no option stays as it is.
  for (const char* plain : {"no option here", "a `Capital` word", "an open ` quote", "``", "`a b`"})
    EXPECT_EQ(tools::cli_text(plain, "run"), plain);
}

TEST(OptionSpelling, CoresMessagesReachTheCommandLineAsFlags) {
  const std::string dir = test::temp_dir("spelling");
  const std::string ball = ball_phantom(dir);
  // An option's check (particles::validate), with the command in front.
  expect_failure("run " + ball + " --threshold 0 -o " + dir + "/a.ply --particles -5",
                 "run: --particles must be between 1 and 10^8 (0: from --spacing)", dir + "/a.ply");
  expect_failure("tetmesh " + ball + " -o " + dir + "/a.msh --grading 0", "tetmesh: --grading must be",
                 dir + "/a.msh");
  // A run's failure that names the option that would mend it.
  expect_failure("run " + ball + " --threshold 0 --particles 1500 --backend cpu -o " + dir +
                     "/b.ply --min-volume 1e9",
                 "--min-volume 1000000000 mm3 drops every structure", dir + "/b.ply");
}

}  // namespace
}  // namespace mpumesh
