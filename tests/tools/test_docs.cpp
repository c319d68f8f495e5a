// The user's documents: the command reference is the program's own help, and the README
// is the short document it promises to be.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "cli_support.h"
#include "io/read_file.h"

namespace mpumesh {
namespace {

const std::string kSource = MPUMESH_SOURCE_DIR;

// `--help` as docs/cli.md shows it: the usage line names the program, not its path.
std::string help(const std::string& sub) {
  std::string out = run(sub + " --help").out;
  const size_t usage = out.find("Usage: ");
  if (usage != std::string::npos) {
    const size_t name = out.find("mpumesh", usage);
    out.replace(usage + 7, name - usage - 7, "");
  }
  return out;
}

std::vector<std::string> subcommands() {
  std::istringstream in(help(""));
  std::vector<std::string> out;
  bool on = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Subcommands:", 0) == 0) on = true;
    else if (on && line.size() > 2) out.push_back(line.substr(2, line.find(' ', 2) - 2));
  }
  return out;
}

TEST(Docs, CliReferenceIsTheProgramsHelp) {
  const std::string doc = read_file(kSource + "/docs/cli.md");
  const std::vector<std::string> subs = subcommands();
  ASSERT_GE(subs.size(), 10u);
  EXPECT_NE(doc.find(help("")), std::string::npos) << "run scripts/cli_doc.sh";
  for (const std::string& s : subs) {
    EXPECT_NE(doc.find("## mpumesh " + s + "\n"), std::string::npos) << s;
    EXPECT_NE(doc.find(help(s)), std::string::npos) << s << ": docs/cli.md is not its --help; run scripts/cli_doc.sh";
  }
}

TEST(Docs, ReadmeIsShortAndPointsIntoTheRepository) {
  const std::string readme = read_file(kSource + "/README.md");
  EXPECT_LE(std::count(readme.begin(), readme.end(), '\n'), 250);
  for (const char* doc : {"docs/method.md", "docs/cli.md", "docs/benchmarks.md"}) {
    EXPECT_TRUE(std::filesystem::exists(kSource + "/" + doc)) << doc;
    EXPECT_NE(readme.find(doc), std::string::npos) << doc;
  }
  for (const char* file : {"README.md", "docs/method.md", "docs/benchmarks.md"}) {
    const std::string text = read_file(kSource + "/" + file);
    EXPECT_EQ(text.find("../shared"), std::string::npos) << file << " points outside the repository";
  }
  // Every image the README shows is in the repository.
  for (size_t at = readme.find("]("); at != std::string::npos; at = readme.find("](", at + 2)) {
    const std::string target = readme.substr(at + 2, readme.find(')', at) - at - 2);
    if (target.rfind("http", 0) == 0 || target[0] == '#') continue;
    EXPECT_TRUE(std::filesystem::exists(kSource + "/" + target)) << target;
  }
}

}  // namespace
}  // namespace mpumesh
