// The houle commands. Each takes its arguments (after the command name) and returns the exit code:
// 0 success, 1 failure while working (I/O), 2 bad input (arguments or scene).
#pragma once
#include <span>

namespace houle::cli {

int cmd_validate(std::span<char* const> args);
int cmd_info(std::span<char* const> args);
int cmd_render(std::span<char* const> args);
int cmd_probe(std::span<char* const> args);
int cmd_map(std::span<char* const> args);
int cmd_bench(std::span<char* const> args);
int cmd_farm(std::span<char* const> args);

}  // namespace houle::cli
