// `wobble diff A B`: compare two images, or two folders of them, with OpenImageIO idiff 2.4's semantics and exit
// codes (image/image_diff.h; -p: image/yee.h) or with FLIP (--metric flip, image/flip.h);
// folders, heatmaps and JUnit reports: app/commands/diff_command.h. Exit status: 0 same or within tolerance,
// 1 warning, 2 failure (also bad arguments), 4 a file cannot be read.
#include <iostream>
#include <memory>

#include "app/cli/commands.h"
#include "app/commands/diff_command.h"
#include "app/scene/input_error.h"

namespace wobble {
namespace {

struct DiffCliOptions {
  DiffCommandOptions command;
  std::string metric = "idiff", fail, warn, channels;
  bool absolute = false, all_subimages = false;
};

// idiff's options, which it spells with one dash (and also with two); CLI11 reads one dash as a one-letter option.
constexpr const char* kIdiffLongOptions[] = {"fail", "failpercent", "hardfail",    "allowfailures", "failrelative",
                                             "warn", "warnpercent", "hardwarn",    "warnrelative",  "scale",
                                             "abs",  "od",          "allsubimages"};

}  // namespace

std::vector<std::string> idiffSpelling(std::vector<std::string> args) {
  if (args.size() < 2 || args[1] != "diff") return args;
  for (std::size_t i = 2; i < args.size(); ++i) {
    if (args[i] == "--") break;
    for (const char* name : kIdiffLongOptions)
      if (args[i] == std::string("-") + name) args[i] = std::string("--") + name;
  }
  return args;
}

void addDiffCommand(CLI::App& app, int& status) {
  auto o = std::make_shared<DiffCliOptions>();
  DiffCommandOptions& c = o->command;
  CLI::App* cmd = app.add_subcommand("diff",
                                     "Compare two images (EXR, HDR, PFM, PNG) or two folders of them like idiff, or "
                                     "with FLIP: exit 0 same or within tolerance, 1 warning, 2 fail, 4 file error");
  cmd->add_option("a", c.a, "First image, or folder of golden images")->required();
  cmd->add_option("b", c.b, "Second image, or folder of new images (same names)")->required();
  cmd->add_option("--metric", o->metric, "idiff (numbers, as OpenImageIO's idiff) or flip (Andersson et al. 2020)")
      ->capture_default_str()
      ->check(CLI::IsMember({"idiff", "flip"}));
  // Spelled as idiff's; idiffSpelling() turns its one-dash spelling (-fail 0.02) into these.
  cmd->add_option("--fail", o->fail,
                  "idiff: a pixel fails when its error exceeds this (default 1e-06). flip: limits such as 0.05 (the "
                  "mean) or mean=0.05,p99=0.5 (mean, max, pNN; default mean=0)");
  cmd->add_option("--failpercent", c.idiff.fail_percent, "Fail when more than this % of the pixels fail")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  const auto nonNegative = CLI::Range(0.0, 1e30);
  cmd->add_option("--hardfail", c.idiff.hard_fail, "Fail when any pixel's error exceeds this")->check(nonNegative);
  cmd->add_option("--allowfailures", c.idiff.allow_failures, "Pass when at most this many pixels fail, by any amount")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--failrelative", c.idiff.fail_relative,
                  "idiff: a value also fails only when |a - b| exceeds this times (|a| + |b|) / 2 (default 0)")
      ->check(nonNegative);
  cmd->add_option("--warn", o->warn,
                  "idiff: a pixel warns when its error exceeds this (default 1e-06). flip: limits as --fail (none)");
  cmd->add_option("--warnpercent", c.idiff.warn_percent, "Warn when more than this % of the pixels warn")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--hardwarn", c.idiff.hard_warn, "Warn when any pixel's error exceeds this")->check(nonNegative);
  cmd->add_option("--warnrelative", c.idiff.warn_relative, "idiff: as --failrelative, for warnings (default 0)")
      ->check(nonNegative);
  cmd->add_flag("-p,--perceptual", c.idiff.perceptual, "idiff -p: also fail on Yee's perceptual test (as idiff 2.4)");
  cmd->add_option("--channels", o->channels,
                  "EXR channels to compare, e.g. R,G,B or noisy.R,G,B (default: the unnamed layer's)");
  cmd->add_option("--layer", c.idiff.channels.layer, "EXR layer to compare, e.g. albedo (its R, G, B, A first)");
  cmd->add_option("-o,--out", c.out,
                  "One pair: write the difference image |A - B| * scale (idiff) or the FLIP heatmap here (PNG). "
                  "Folders: a folder for the heatmaps of the pairs that warn or fail");
  cmd->add_flag("--od", c.idiff.difference_only_if_different,
                "idiff -od: write --out only when the images differ (a max error above 0)");
  cmd->add_flag("--abs", o->absolute, "idiff -abs: the difference image is |A - B| (wobble's always is)");
  cmd->add_flag("-a,--allsubimages", o->all_subimages,
                "idiff -a: every subimage and MIP level; wobble's images have one each (a multi-part or MIP-mapped "
                "EXR is refused)");
  cmd->add_option("--heatmap", c.heatmap,
                  "One pair: write the heatmap of the per-pixel error (magma) here when the pair warns or fails");
  cmd->add_option("--scale", c.idiff.diff_scale, "Multiplier of the difference image and idiff heatmaps")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--junit", c.junit, "Write a JUnit XML report here (one test case per image pair)");
  cmd->add_option("--ppd", c.pixels_per_degree,
                  "FLIP: the observer's pixels per degree (default: a 0.7 m wide 4K display at 0.7 m)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("-v,--verbose", c.verbose, "Print the full report of passing pairs too");
  cmd->add_flag("-q,--quiet", c.quiet, "Print nothing: the exit status says it all (idiff -q)");
  cmd->footer(
      "Examples:\n  wobble diff golden.png new.png --fail 0.02 --failpercent 1 --hardfail 0.25 --out d.png\n"
      "  wobble diff frame.exr golden.exr --layer albedo\n"
      "  wobble diff tests/golden out/frames --metric flip --fail mean=0.02,p99=0.3 --out heatmaps --junit r.xml\n"
      "As idiff: when no pixel is over --fail (or at most --allowfailures are), the images pass, whatever the warn\n"
      "options say; images of different size or channel count are compared over both, missing values as 0.\n"
      "Folders: files of the same name are compared; a file in only one of them fails. See docs/rendering-tests.md.\n"
      "idiff's one-dash spelling works too: wobble diff -fail 0.02 -failpercent 1 -o d.png a.png b.png.\n"
      "Exit status: 0 pass, 1 warning, 2 fail (also bad arguments), 4 file error (the worst pair's).");
  cmd->callback([o, &status] {
    DiffCommandOptions command = o->command;
    command.metric = o->metric == "flip" ? DiffMetric::Flip : DiffMetric::Idiff;
    if (!o->channels.empty()) command.idiff.channels.channels = image::splitChannelList(o->channels);
    command.all_subimages = o->all_subimages;
    if (o->all_subimages)
      for (const std::filesystem::path& file : {command.a, command.b})
        if (const int n = image::subimageCount(file); n > 1)
          throw InputError("-a (--allsubimages): " + file.string() + " holds " + std::to_string(n) +
                           " subimages or MIP levels; wobble diff compares one image per file (an EXR's first part "
                           "at full resolution): compare it with idiff, or without -a");
    if (command.metric == DiffMetric::Flip) {
      if (!o->fail.empty()) command.flip_fail = parseFlipThresholds("--fail", o->fail);
      if (!o->warn.empty()) command.flip_warn = parseFlipThresholds("--warn", o->warn);
    } else {
      const auto number = [](const std::string& flag, const std::string& text, float& to) {
        if (text.empty()) return;
        try {
          std::size_t used = 0;
          to = std::stof(text, &used);
          if (used == text.size() && to >= 0) return;
        } catch (const std::exception&) {
        }
        throw InputError(flag + " '" + text + "': expected a number >= 0 (the idiff metric's pixel threshold)");
      };
      number("--fail", o->fail, command.idiff.fail);
      number("--warn", o->warn, command.idiff.warn);
    }
    status = runDiff(command, std::cout).exitCode();
  });
}

}  // namespace wobble
