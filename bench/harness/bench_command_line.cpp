#include "bench_command_line.hpp"

#include <cstdlib>
#include <iostream>
#include <stdexcept>

namespace bench {

BenchCommandLine::BenchCommandLine(std::string name, std::string usage)
    : name_(std::move(name)), usage_(std::move(usage)), app_(name_) {
  app_.set_help_flag();
}

void BenchCommandLine::parse(int argc, char** argv) {
  bool help = false;
  app_.add_flag("-h,--help", help);
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (help) {
      std::cout << usage_;
      std::exit(0);
    }
    throw std::invalid_argument(error.what());
  }
  if (help) {
    std::cout << usage_;
    std::exit(0);
  }
}

int run_main(const BenchCommandLine& command_line, const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::invalid_argument& error) {
    std::cerr << command_line.name() << ": " << error.what() << "\n" << command_line.usage();
    return 2;
  } catch (const std::exception& error) {
    std::cerr << command_line.name() << ": " << error.what() << "\n";
    return 1;
  }
}

}  // namespace bench
