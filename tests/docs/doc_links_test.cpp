// The documentation's links hold: every relative link and image in the repository's Markdown pages (README.md,
// ARCHITECTURE.md, scenes/README.md, docs/, ...) names a file or folder that exists inside the repository, and every
// #anchor names a heading of its page as GitHub spells it (lower case, punctuation dropped, spaces as hyphens, a
// repeated heading numbered -1, -2, ...). Every page in docs/ is linked from README.md and from the index
// docs/README.md. The checker itself is tried first on pages with known faults.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The page's lines outside fenced code blocks, with inline code spans blanked (a link inside code is not a link).
std::vector<std::string> proseLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  bool fenced = false;
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find_first_not_of(' ');
    if (first != std::string::npos && (line.compare(first, 3, "```") == 0 || line.compare(first, 3, "~~~") == 0)) {
      fenced = !fenced;
      lines.emplace_back();
      continue;
    }
    if (fenced) {
      lines.emplace_back();
      continue;
    }
    static const std::regex code("`[^`]*`");
    lines.push_back(std::regex_replace(line, code, "``"));
  }
  return lines;
}

// GitHub's anchor for a heading: inline markup reduced to its text, lower case, every character but letters, digits,
// spaces, '-' and '_' dropped, spaces turned into '-'.
std::string slug(std::string heading) {
  static const std::regex link(R"(\[([^\]]*)\]\([^)]*\))");
  heading = std::regex_replace(heading, link, "$1");
  std::string out;
  for (unsigned char c : heading) {
    if (std::isalnum(c) || c == '-' || c == '_' || c >= 0x80) out += static_cast<char>(std::tolower(c));
    else if (c == ' ') out += '-';
  }
  return out;
}

// The anchors a page offers: its headings' slugs (repeats numbered as GitHub does) and explicit <a name|id="...">.
std::set<std::string> anchors(const std::string& text) {
  std::set<std::string> result;
  std::map<std::string, int> seen;
  std::istringstream in(text);
  bool fenced = false;
  static const std::regex heading(R"(^ {0,3}#{1,6}\s+(.*?)\s*#*\s*$)");
  static const std::regex html(R"(<a\s+(?:name|id)\s*=\s*"([^"]+)\")");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0 || line.rfind("~~~", 0) == 0) fenced = !fenced;
    if (fenced) continue;
    std::smatch m;
    if (std::regex_match(line, m, heading)) {
      const std::string base = slug(m[1]);
      const int n = seen[base]++;
      result.insert(n == 0 ? base : base + "-" + std::to_string(n));
    }
    for (auto it = std::sregex_iterator(line.begin(), line.end(), html); it != std::sregex_iterator(); ++it)
      result.insert((*it)[1]);
  }
  return result;
}

// The link targets of a page: inline links and images [text](target "title"), reference definitions [id]: target,
// and HTML src= / href= attributes.
std::vector<std::string> targets(const std::string& text) {
  std::vector<std::string> result;
  static const std::regex inline_link(R"(\]\(\s*<?([^)\s>]*)>?(?:\s+"[^"]*")?\s*\))");
  static const std::regex definition(R"(^ {0,3}\[[^\]]+\]:\s*<?([^\s>]+)>?)");
  static const std::regex attribute(R"((?:src|href)\s*=\s*"([^"]*)\")");
  for (const std::string& line : proseLines(text)) {
    for (const std::regex* r : {&inline_link, &definition, &attribute})
      for (auto it = std::sregex_iterator(line.begin(), line.end(), *r); it != std::sregex_iterator(); ++it)
        result.push_back((*it)[1]);
  }
  return result;
}

std::string percentDecoded(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// A resolved link: the file (inside root), or why it is broken.
struct Resolved {
  fs::path file;
  std::string fault;
};

Resolved resolve(const fs::path& root, const fs::path& page, const std::string& target) {
  static const std::regex scheme("^[a-zA-Z][a-zA-Z0-9+.-]*:");
  if (std::regex_search(target, scheme)) return {};  // http:, https:, mailto: are not checked here
  const auto hash = target.find('#');
  const std::string path_part = percentDecoded(target.substr(0, hash));
  const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
  const fs::path file = path_part.empty() ? page : fs::weakly_canonical(page.parent_path() / path_part);
  const fs::path relative = file.lexically_relative(root);
  if (relative.empty() || *relative.begin() == "..") return {file, "points outside the repository"};
  if (!fs::exists(file)) return {file, "no such file"};
  if (!anchor.empty() && file.extension() == ".md" && !anchors(readFile(file)).count(anchor))
    return {file, "no heading with the anchor #" + anchor + " in " + relative.string()};
  return {file, ""};
}

// "page: target: fault" for every broken link of page.
std::vector<std::string> brokenLinks(const fs::path& root, const fs::path& page) {
  std::vector<std::string> broken;
  for (const std::string& target : targets(readFile(page))) {
    if (target.empty()) {
      broken.push_back(page.lexically_relative(root).string() + ": an empty link");
      continue;
    }
    const Resolved r = resolve(root, page, target);
    if (!r.fault.empty()) broken.push_back(page.lexically_relative(root).string() + ": " + target + ": " + r.fault);
  }
  return broken;
}

// The files page links to (existing ones), as paths relative to root.
std::set<std::string> linkedFiles(const fs::path& root, const fs::path& page) {
  std::set<std::string> files;
  for (const std::string& target : targets(readFile(page))) {
    const Resolved r = resolve(root, page, target);
    if (r.fault.empty() && !r.file.empty()) files.insert(r.file.lexically_relative(root).string());
  }
  return files;
}

// The repository's Markdown pages, outside build trees, output and .git.
std::vector<fs::path> markdownPages(const fs::path& root) {
  std::vector<fs::path> pages;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name.rfind("build", 0) == 0 || name == "out" || name[0] == '.')) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && it->path().extension() == ".md") pages.push_back(it->path());
  }
  return pages;
}

class DocLinksChecker : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("wobble_doc_links_" + std::to_string(::getpid()));
    fs::create_directories(root_ / "docs");
    root_ = fs::canonical(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(root_ / name) << text;
    return root_ / name;
  }
  fs::path root_;
};

TEST_F(DocLinksChecker, FindsEachKindOfBrokenLink) {
  write("docs/a.md", "# Render quality\n## `wobble diff`: compare images\n## Notes\n## Notes\n<a name=\"kept\"></a>\n");
  write("pic.png", "");
  const fs::path page = write(
      "README.md",
      "[ok](docs/a.md) ![img](pic.png) [anchor](docs/a.md#render-quality) "
      "[code](docs/a.md#wobble-diff-compare-images)\n"
      "[second](docs/a.md#notes-1) [html](docs/a.md#kept) [self](#a-heading) [web](https://example.com/x.md)\n"
      "# A heading\n"
      "`[in code](missing.md)`\n```\n[in a fence](missing.md)\n```\n"
      "[gone](docs/missing.md) ![gone image](docs/missing.png) [bad anchor](docs/a.md#render-qualityx)\n"
      "[outside](../elsewhere.md) [no third](docs/a.md#notes-2)\n[ref]: docs/nothing.md\n<img src=\"none.png\">\n");
  const std::vector<std::string> broken = brokenLinks(root_, page);
  const std::vector<std::string> expected = {
      "README.md: docs/missing.md: no such file",
      "README.md: docs/missing.png: no such file",
      "README.md: docs/a.md#render-qualityx: no heading with the anchor #render-qualityx in docs/a.md",
      "README.md: ../elsewhere.md: points outside the repository",
      "README.md: docs/a.md#notes-2: no heading with the anchor #notes-2 in docs/a.md",
      "README.md: docs/nothing.md: no such file",
      "README.md: none.png: no such file",
  };
  EXPECT_EQ(broken, expected);
}

TEST_F(DocLinksChecker, SlugsFollowGitHub) {
  EXPECT_EQ(slug("`wobble diff`: compare images"), "wobble-diff-compare-images");
  EXPECT_EQ(slug("Time in Embree against time shading, beside Cycles"),
            "time-in-embree-against-time-shading-beside-cycles");
  EXPECT_EQ(slug("The course framework's constants"), "the-course-frameworks-constants");
  EXPECT_EQ(slug("In Blender (3.4 or later)"), "in-blender-34-or-later");
  EXPECT_EQ(slug("snake_case and [a link](x.md)"), "snake_case-and-a-link");
}

TEST(DocLinks, EveryRelativeLinkAndImageResolves) {
  const fs::path root = fs::canonical(WOBBLE_SOURCE_DIR);
  const std::vector<fs::path> pages = markdownPages(root);
  std::set<std::string> names;
  for (const fs::path& p : pages) names.insert(p.lexically_relative(root).string());
  for (const char* required : {"README.md", "ARCHITECTURE.md", "scenes/README.md", "docs/README.md"})
    EXPECT_TRUE(names.count(required)) << required << " was not found among the pages";
  for (const fs::path& page : pages)
    for (const std::string& fault : brokenLinks(root, page)) ADD_FAILURE() << fault;
}

TEST(DocLinks, EveryDocsPageIsLinkedFromTheReadmeAndTheIndex) {
  const fs::path root = fs::canonical(WOBBLE_SOURCE_DIR);
  const std::set<std::string> from_readme = linkedFiles(root, root / "README.md");
  const std::set<std::string> from_index = linkedFiles(root, root / "docs/README.md");
  EXPECT_TRUE(from_readme.count("docs/README.md")) << "README.md does not link the index docs/README.md";
  for (const auto& entry : fs::directory_iterator(root / "docs")) {
    if (entry.path().extension() != ".md" || entry.path().filename() == "README.md") continue;
    const std::string name = entry.path().lexically_relative(root).string();
    EXPECT_TRUE(from_readme.count(name)) << name << " is not linked from README.md";
    EXPECT_TRUE(from_index.count(name)) << name << " is not linked from docs/README.md";
  }
}

}  // namespace
