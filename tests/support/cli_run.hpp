// Running the command line from a test: its exit status, stdout and stderr.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace isoquad::test {

struct CliRun {
  int status;
  std::string out, err;
};

// Runs a shell command, capturing its exit status, stdout and stderr.
inline CliRun shell(const std::string& command) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "_" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const auto out = dir / ("isoquad_cli_out_" + tag), err = dir / ("isoquad_cli_err_" + tag);
  const std::string cmd = command + " >" + out.string() + " 2>" + err.string();
  const int raw = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CliRun r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

// Runs `argv` (a program and its arguments, no shell) with stderr on a pseudo-terminal, so that
// isatty(2) holds, and stdout to /dev/null; `err` is what it printed there, byte for byte (the
// terminal is raw: no \n -> \r\n). Linked with util (openpty).
inline CliRun on_terminal(const std::vector<std::string>& argv) {
  int master = -1, slave = -1;
  if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) return {-1, "", "no pty"};
  termios raw{};
  ::tcgetattr(slave, &raw);
  ::cfmakeraw(&raw);
  ::tcsetattr(slave, TCSANOW, &raw);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, slave, STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, slave);
  posix_spawn_file_actions_addclose(&actions, master);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = ::posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(slave);  // the child's copy is the only one left: reads end (EIO) when it exits
  std::string err;
  if (spawned == 0) {
    char buffer[4096];
    for (;;) {
      const ssize_t n = ::read(master, buffer, sizeof buffer);
      if (n > 0) {
        err.append(buffer, std::size_t(n));
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else {
        break;
      }
    }
  }
  ::close(master);
  int raw_status = 0;
  if (spawned != 0 || ::waitpid(pid, &raw_status, 0) != pid) return {-1, "", err};
  return {WIFEXITED(raw_status) ? WEXITSTATUS(raw_status) : -1, "", err};
}

}  // namespace isoquad::test
