#pragma once
// Shared Boost.Program_options plumbing for subcommands.

#include <boost/program_options.hpp>
#include <iostream>

#include "apps/commands.hpp"

namespace lhr::app {

namespace po = boost::program_options;

// Parses args against visible options plus positionals; prints help and
// returns false when --help was given.
// `hidden` declares the positional arguments, which the usage line describes.
inline bool parse_command_line(const Args& args, const char* usage, const po::options_description& visible,
                               const po::options_description& hidden,
                               const po::positional_options_description& positional, po::variables_map& vm) {
  po::options_description all;
  all.add(visible).add(hidden);
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout << usage << "\n\n" << visible << "\n";
    return false;
  }
  po::notify(vm);
  return true;
}

}  // namespace lhr::app
