// pd-mesh: placeholder entry point (see docs/architecture.md).
#include <boost/program_options.hpp>
#include <iostream>

#include "cli.hpp"
#include "pd/version.hpp"

int main(int argc, char** argv) {
  return pd::run_tool("pd-mesh", [&] {
    namespace po = boost::program_options;
    po::options_description options("pd-mesh options");
    options.add_options()("help,h", "show this help")("version", "print the version");
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, options), vm);
    if (vm.count("help")) { std::cout << options; return 0; }
    if (vm.count("version")) { std::cout << "pd-mesh " << pd::version_string << "\n"; return 0; }
    throw pd::Error("not implemented yet");
  });
}
