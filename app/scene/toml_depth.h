// A bound on how deeply a TOML text nests, from a scan that needs no parse. toml++ builds (and frees) nested
// tables and arrays recursively, so a table header nested 50 000 levels deep overflows the stack before the parser
// could report anything; the scene reader refuses such a text up front (scene_limits.h: kMaxNestingDepth).
#pragma once
#include <optional>
#include <string_view>

namespace wobble {

struct NestingExcess {
  int line = 0;   // 1-based
  int depth = 0;  // the bound reached on that line
};

// The first line whose nesting bound exceeds max_depth. The bound is the number of open '[' and '{' (carried across
// lines: arrays may span them) plus the dots of the dotted keys on the line, all outside strings and comments. It
// may overcount (a dot in a quoted key part), never undercount.
std::optional<NestingExcess> findExcessNesting(std::string_view text, int max_depth);

}  // namespace wobble
