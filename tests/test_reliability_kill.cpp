// Reliability (issue 14, item 8): `anisurf adapt -o OUT.mesh` killed with
// SIGKILL at the start of each file's write, and at moments spread over a
// whole run, leaves the previous OUT.mesh + OUT.sol pair byte for byte or the
// new pair, never a mix; the next run into the same outputs removes the
// killed runs' temporaries. The kills are timed by inotify on the output
// directory (the creation of each temporary).
#include <doctest/doctest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
namespace fs = std::filesystem;

namespace {

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Pair {
  std::string mesh, sol;
  bool operator==(const Pair& o) const { return mesh == o.mesh && sol == o.sol; }
};

Pair pair_in(const fs::path& dir) { return {bytes_of(dir / "out.mesh"), bytes_of(dir / "out.sol")}; }

std::vector<std::string> temporaries_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) out.push_back(e.path().filename().string());
  return out;
}

pid_t start_adapt(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    static std::string binary = ANISURF_BINARY;
    argv.push_back(binary.data());
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execv(ANISURF_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

// Runs adapt and kills it when a file whose name starts with `prefix` and
// contains `part` is created in `dir`. Returns true if it was killed so.
bool adapt_killed_at_creation(const fs::path& dir, const std::vector<std::string>& args,
                              const std::string& prefix, const std::string& part) {
  const int fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  REQUIRE(fd >= 0);
  REQUIRE(inotify_add_watch(fd, dir.c_str(), IN_CREATE) >= 0);
  const pid_t pid = start_adapt(args);
  bool killed = false;
  int status = 0;
  while (!killed) {
    if (waitpid(pid, &status, WNOHANG) == pid) break;  // ended before the file was created
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 10) <= 0) continue;
    alignas(inotify_event) char buf[4096];
    const ssize_t n = read(fd, buf, sizeof buf);
    for (ssize_t at = 0; at < n && !killed;) {
      const auto* e = reinterpret_cast<const inotify_event*>(buf + at);
      const std::string name = e->len ? e->name : "";
      if (name.rfind(prefix, 0) == 0 && name.find(part, prefix.size()) != std::string::npos) {
        kill(pid, SIGKILL);
        killed = true;
      }
      at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
    }
  }
  if (killed) waitpid(pid, &status, 0);
  close(fd);
  return killed && WIFSIGNALED(status);
}

// Runs adapt and kills it after `delay`; returns true if it was still running.
bool adapt_killed_after(const std::vector<std::string>& args, std::chrono::microseconds delay) {
  const pid_t pid = start_adapt(args);
  std::this_thread::sleep_for(delay);
  const bool killed = kill(pid, SIGKILL) == 0;
  int status = 0;
  waitpid(pid, &status, 0);
  return killed && WIFSIGNALED(status);
}

int run_adapt(const std::vector<std::string>& args) {
  const pid_t pid = start_adapt(args);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("reliability: adapt killed at any moment leaves the old pair or the new one, temporaries removed next run") {
  const fs::path dir = test::temp_dir("kill_pair");
  const std::string in = (dir / "in.mesh").string(), out = (dir / "out.mesh").string();
  {
    SurfaceMesh m;
    build_mesh(test::icosphere(4), m);
    save_mesh(in, m);
  }
  const std::vector<std::string> first = {"adapt", in, "--size", "0.2", "-v", "0", "-o", out};
  const std::vector<std::string> second = {"adapt", in, "--size", "0.1", "-v", "0", "-o", out};
  // The new pair, from a clean run; then the old one in place.
  REQUIRE(run_adapt(second) == 0);
  const Pair new_pair = pair_in(dir);
  REQUIRE(run_adapt(first) == 0);
  const Pair old_pair = pair_in(dir);
  REQUIRE_FALSE(old_pair == new_pair);

  // Killed as the temporary of each file of the set ("out.tmp-PID.mesh",
  // "out.tmp-PID.sol"; not the writability probes "out.mesh.tmp-PID") is
  // created: the old pair stays.
  for (const std::string ext : {".mesh", ".sol"}) {
    CAPTURE(ext);
    REQUIRE(adapt_killed_at_creation(dir, second, "out.tmp-", ext));
    CHECK(pair_in(dir) == old_pair);
    CHECK_FALSE(temporaries_in(dir).empty());  // the killed run's, removed by the next run
  }
  // Killed at moments spread over a whole run (load, adaptation, writing,
  // and the renames at its end): once the next run has completed what a
  // killed commit recorded (as `adapt` does before writing or reading these
  // files), the old pair or the new one, whole.
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(run_adapt(second) == 0);
  const auto run_time = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
  REQUIRE(run_adapt(first) == 0);
  int killed = 0;
  for (int k = 1; k <= 13; ++k) {
    CAPTURE(k);
    if (adapt_killed_after(second, run_time * k / 13)) ++killed;
    finish_interrupted_commits(out);
    const Pair now = pair_in(dir);
    CHECK((now == old_pair || now == new_pair));
    if (now == new_pair) REQUIRE(run_adapt(first) == 0);  // the old pair back for the next moment
  }
  CHECK(killed >= 6);
  // The next complete run leaves no temporary and the new pair.
  REQUIRE(run_adapt(second) == 0);
  CHECK(temporaries_in(dir).empty());
  CHECK(pair_in(dir) == new_pair);
}
