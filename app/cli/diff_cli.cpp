// `wobble diff A.png B.png`: compare two images with OpenImageIO idiff 2.4's semantics and exit codes
// (render/image_diff.h): 0 the same or within tolerance, 1 warning, 2 failure, 4 a file cannot be read.
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "render/image/image_diff.h"

namespace wobble {
namespace {

struct DiffCliOptions {
  std::filesystem::path a, b, out;
  render::DiffOptions diff;
};

}  // namespace

void addDiffCommand(CLI::App& app, int& status) {
  auto o = std::make_shared<DiffCliOptions>();
  CLI::App* cmd = app.add_subcommand("diff",
                                     "Compare two images like idiff: exit 0 same or within tolerance, "
                                     "1 warning, 2 fail, 4 file error");
  cmd->add_option("a", o->a, "First image (PNG)")->required();
  cmd->add_option("b", o->b, "Second image (PNG)")->required();
  const auto nonNegative = CLI::Range(0.0, 1e30);
  cmd->add_option("--fail", o->diff.fail, "A pixel fails when its error exceeds this (values in [0, 1])")
      ->capture_default_str()
      ->check(nonNegative);
  cmd->add_option("--failpercent", o->diff.fail_percent, "Fail when more than this % of the pixels fail")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--hardfail", o->diff.hard_fail, "Fail when any pixel's error exceeds this")->check(nonNegative);
  cmd->add_option("--allowfailures", o->diff.allow_failures, "Pass when at most this many pixels fail, by any amount")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--warn", o->diff.warn, "A pixel warns when its error exceeds this")
      ->capture_default_str()
      ->check(nonNegative);
  cmd->add_option("--warnpercent", o->diff.warn_percent, "Warn when more than this % of the pixels warn")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--hardwarn", o->diff.hard_warn, "Warn when any pixel's error exceeds this")->check(nonNegative);
  cmd->add_option("--out", o->out, "Write the difference image |A - B| * scale here (PNG)");
  cmd->add_option("--scale", o->diff.diff_scale, "Multiplier of the difference image")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->footer(
      "Example:\n  wobble diff golden.png new.png --fail 0.02 --failpercent 1 --hardfail 0.25 --out d.png\n"
      "As idiff: when no pixel is over --fail (or at most --allowfailures are), the images pass, whatever the warn\n"
      "options say; images of different size or channel count are compared over both, missing values as 0.\n"
      "Exit status: 0 pass, 1 warning, 2 fail (also bad arguments), 4 file error.");
  cmd->callback([o, &status] {
    const render::DiffResult r = render::diffFiles(o->a, o->b, o->diff, o->out);
    std::printf("%s\n", r.message.c_str());
    status = r.exitCode();
  });
}

}  // namespace wobble
