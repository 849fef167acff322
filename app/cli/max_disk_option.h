// --max-disk SIZE on the commands that write frames (`wobble run`, `wobble render`): the most bytes the command may
// write, in --max-memory's syntax (e.g. 20GB, 500MB; KB = 1024 bytes). Before writing anything the command estimates
// what it will write (app/output/disk_budget.h) and refuses (exit 2) above this or above the free space of --out's file
// system, whichever is less; without it, the free space alone.
#pragma once
#include <CLI/CLI.hpp>

namespace wobble {

void addMaxDiskOption(CLI::App& cmd);

}  // namespace wobble
