#include "cli/cli.h"

#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace anisurf::cli {

// Commands defined in cmd_*.cpp.
Command info_command();
Command convert_command();
Command quality_command();
Command metric_command();
Command reconstruct_command();
Command adapt_command();
Command distance_command();

std::vector<Command> engine_commands() {
  std::vector<Command> list;
  list.push_back(info_command());
  list.push_back(convert_command());
  list.push_back(metric_command());
  list.push_back(quality_command());
  list.push_back(reconstruct_command());
  list.push_back(adapt_command());
  list.push_back(distance_command());
  return list;
}

namespace {

void print_overview(const std::vector<Command>& commands) {
  std::cout << "anisurf: anisotropic surface mesh adaptation (Castro-Diaz & Hecht 1995)\n\n"
               "usage: anisurf COMMAND [ARGS...]    (anisurf COMMAND --help for details)\n\ncommands:\n";
  for (const auto& c : commands) {
    std::string pad(c.name.size() < 13 ? 13 - c.name.size() : 1, ' ');
    std::cout << "  " << c.name << pad << c.summary << "\n";
  }
  std::cout << "\nexample: anisurf info mesh.mesh --json\n";
}

}  // namespace

int run(int argc, char** argv, const std::vector<Command>& commands) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    if (args.size() >= 2 && args[0] == "help") {
      for (const auto& c : commands)
        if (c.name == args[1]) {
          std::cout << c.help;
          return 0;
        }
    }
    print_overview(commands);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "anisurf 0.1.0\n";
    return 0;
  }
  const Command* cmd = nullptr;
  for (const auto& c : commands)
    if (c.name == args[0]) cmd = &c;
  if (!cmd) {
    std::cerr << "anisurf: unknown command '" << args[0] << "'\n\n";
    print_overview(commands);
    return 2;
  }
  std::vector<std::string> rest(args.begin() + 1, args.end());
  for (const auto& a : rest)
    if (a == "--help" || a == "-h") {
      std::cout << cmd->help;
      return 0;
    }
  try {
    return cmd->run(rest);
  } catch (const UsageError& e) {
    std::cerr << "anisurf " << cmd->name << ": " << e.message << "\n\n" << cmd->help;
    return 2;
  } catch (const Error& e) {
    std::cerr << "anisurf " << cmd->name << ": error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "anisurf " << cmd->name << ": error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "anisurf " << cmd->name << ": internal error: " << e.what() << "\n";
    return 3;
  }
}

bool ArgParser::flag(const std::string& name) {
  for (auto it = args_.begin(); it != args_.end(); ++it)
    if (*it == name) {
      args_.erase(it);
      return true;
    }
  return false;
}

bool ArgParser::flag(const std::string& name, const std::string& alias) {
  bool a = flag(name);
  bool b = flag(alias);
  return a || b;
}

std::string ArgParser::option(const std::string& name) {
  for (auto it = args_.begin(); it != args_.end(); ++it) {
    if (*it == name) {
      if (it + 1 == args_.end()) throw UsageError{"option " + name + " needs a value"};
      std::string v = *(it + 1);
      args_.erase(it, it + 2);
      return v;
    }
    if (it->rfind(name + "=", 0) == 0) {
      std::string v = it->substr(name.size() + 1);
      args_.erase(it);
      return v;
    }
  }
  return {};
}

std::string ArgParser::option(const std::string& name, const std::string& alias) {
  std::string v = option(name);
  return v.empty() ? option(alias) : v;
}

double ArgParser::option_double(const std::string& name, double fallback) {
  std::string v = option(name);
  if (v.empty()) return fallback;
  try {
    std::size_t used = 0;
    double d = std::stod(v, &used);
    if (used != v.size()) throw std::invalid_argument(v);
    return d;
  } catch (const std::exception&) {
    throw UsageError{"option " + name + " expects a number, got '" + v + "'"};
  }
}

BuildOptions weld_build_options(ArgParser& p) {
  BuildOptions o;
  const std::string tolerance = p.option("--weld");
  if (tolerance.empty()) return o;
  double weld = -1;
  try {
    std::size_t used = 0;
    weld = std::stod(tolerance, &used);
    if (used != tolerance.size()) weld = -1;
  } catch (const std::exception&) {
  }
  if (!(weld >= 0 && weld < 0.1))
    throw UsageError{"--weld expects a tolerance relative to the bounding box in [0, 0.1), got '" + tolerance + "'"};
  o.merge = BuildOptions::Merge::Always;
  o.merge_tolerance = weld;
  return o;
}

std::vector<std::string> ArgParser::positionals() const {
  for (const auto& a : args_)
    if (a.size() > 1 && a[0] == '-' && !(a[1] >= '0' && a[1] <= '9') && a[1] != '.')
      throw UsageError{"unknown option '" + a + "'"};
  return args_;
}

}  // namespace anisurf::cli
