// The `anisurf` command line: a list of subcommands, each with a one-line
// summary, a --help text with an example, and a function returning the exit
// code. Commands that need OpenGL are added by the app when built with GL.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "mesh/build.h"

namespace anisurf::cli {

struct Command {
  std::string name;     // e.g. "info"
  std::string summary;  // one line for `anisurf --help`
  std::string help;     // full text for `anisurf NAME --help` (usage, options, example)
  std::function<int(const std::vector<std::string>& args)> run;  // args after NAME
};

// Commands of the engine-only command line (info, convert, ...).
std::vector<Command> engine_commands();

// Runs `argv` against `commands`; handles --help, unknown commands and
// exceptions (message on stderr, exit code 1 for bad input, 2 for bad usage).
int run(int argc, char** argv, const std::vector<Command>& commands);

// Thrown by commands on a bad command line (exit code 2, with the usage).
struct UsageError {
  std::string message;
};

// Small helper to walk a command line: positional arguments and options.
class ArgParser {
 public:
  explicit ArgParser(const std::vector<std::string>& args) : args_(args) {}
  // True if the flag is present (removes it).
  bool flag(const std::string& name);
  bool flag(const std::string& name, const std::string& alias);
  // Value of "--name VALUE" (removes both); empty if absent.
  std::string option(const std::string& name);
  std::string option(const std::string& name, const std::string& alias);
  double option_double(const std::string& name, double fallback);
  // Remaining positional arguments; throws UsageError on a leftover "-x" option.
  std::vector<std::string> positionals() const;

 private:
  std::vector<std::string> args_;
};

// `--weld TOL` of the commands that read a mesh to remesh or to build a
// metric on: the vertices closer than TOL x the bounding box diagonal merged,
// in every format (a soup of any format builds as one surface). Without the
// option, the format's default (STL and glTF merged, others kept apart).
// Throws UsageError unless 0 <= TOL < 0.1.
BuildOptions weld_build_options(ArgParser& p);

}  // namespace anisurf::cli
