// A script's `save` or `screenshot` into a missing directory is refused on
// its line, naming the path, and creates nothing.
#include <doctest/doctest.h>
#ifdef ANISURF_WITH_GL

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "editor/script.h"
#include "editor/session.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;

namespace {

std::string assets_file(const std::string& name) {
  return (std::filesystem::path(ANISURF_TEST_DATA_DIR) / ".." / ".." / "assets" / name).string();
}

// Runs a script of `open demo; LINE` and returns its error ("" if none).
std::string script_error(const std::filesystem::path& script, const std::string& line, const ScriptHost& host = {}) {
  std::ofstream(script) << "open " << assets_file("demo.mesh") << " " << assets_file("demo.sol") << "\n" << line << "\n";
  EditorSession s;
  ViewState v;
  try {
    for (const auto& l : read_script(script.string())) execute(l, s, v, host);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("editor scripts: save into a missing directory is refused, nothing created") {
  const auto dir = test::temp_dir("editor_save_missing_dir");
  const auto script = dir / "save.anisurf";
  const std::string at = script.string() + ":2: ";
  for (const std::string& line : {"save " + (dir / "missing" / "deeper" / "out.mesh").string(),
                                  "save " + (dir / "out.mesh").string() + " " + (dir / "missing" / "out.sol").string()}) {
    const std::string err = script_error(script, line);
    CAPTURE(line);
    CAPTURE(err);
    CHECK(err.find(at + "save: ") != std::string::npos);
    CHECK(err.find("directory '" + (dir / "missing").string()) != std::string::npos);
    CHECK(err.find("does not exist") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "missing"));
    CHECK(!std::filesystem::exists(dir / "out.mesh"));  // neither file of the pair
  }
  // A file where a directory is expected is refused the same way.
  std::ofstream(dir / "plain") << "x";
  const std::string err = script_error(script, "save " + (dir / "plain" / "out.mesh").string());
  CHECK(err.find("is not a directory") != std::string::npos);
  // An existing directory saves.
  CHECK(script_error(script, "save " + (dir / "out.mesh").string() + " " + (dir / "out.sol").string()) == "");
  CHECK(std::filesystem::exists(dir / "out.mesh"));
  CHECK(std::filesystem::exists(dir / "out.sol"));
}

TEST_CASE("editor scripts: a screenshot into a missing directory is refused on its line, nothing created") {
  const auto dir = test::temp_dir("editor_shot_missing_dir");
  const auto script = dir / "shot.anisurf";
  std::vector<std::string> shots;
  ScriptHost host;
  host.screenshot = [&](const std::string& png) { shots.push_back(png); };
  const std::string err = script_error(script, "screenshot " + (dir / "missing" / "x.png").string(), host);
  CAPTURE(err);
  CHECK(err.find(script.string() + ":2: screenshot: ") != std::string::npos);
  CHECK(err.find("cannot be written") != std::string::npos);
  CHECK(shots.empty());
  CHECK(!std::filesystem::exists(dir / "missing"));
  // An existing directory takes the screenshot.
  CHECK(script_error(script, "screenshot " + (dir / "x.png").string(), host) == "");
  CHECK(shots.size() == 1);
}

#endif  // ANISURF_WITH_GL
