#pragma once
// Subcommands of the `lhr` executable. Each parses its own options and calls
// the libraries; it returns the process exit code.

#include <string>
#include <vector>

namespace lhr::app {

// Exit codes shared by all subcommands.
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // bad input, failed check, I/O error
constexpr int kExitUsage = 2;    // bad command line

using Args = std::vector<std::string>;  // arguments after the subcommand name

int run_mesh(const Args& args);
int run_validate(const Args& args);
int run_scene(const Args& args);
int run_solve(const Args& args);
int run_reference(const Args& args);
int run_compare(const Args& args);
int run_bench(const Args& args);

}  // namespace lhr::app
