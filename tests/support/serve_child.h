// ServeChild: `tinbase serve STORE --listen 127.0.0.1:0` as a child process of a test, with the
// port it printed. Header-only.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace tinbase::testing {

// `tinbase serve STORE --listen 127.0.0.1:0` as a child process, stopped with SIGTERM
// (Stop) or SIGKILL (Kill).
class ServeChild {
 public:
  explicit ServeChild(const std::string& store) {
    int out[2];
    if (pipe(out) != 0) {
      ADD_FAILURE() << "pipe failed";
      return;
    }
    pid_ = fork();
    if (pid_ == 0) {
      // A test that dies (an uncaught exception aborts it) takes its server with it; an orphaned
      // server would hold CTest's output pipe open until the test's timeout.
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      dup2(out[1], STDOUT_FILENO);
      close(out[0]);
      close(out[1]);
      execl(TINBASE_CLI, TINBASE_CLI, "serve", store.c_str(), "--listen", "127.0.0.1:0",
            static_cast<char*>(nullptr));
      _exit(127);
    }
    close(out[1]);
    stdout_ = out[0];
    // "serving STORE on http://127.0.0.1:PORT/"
    std::string line;
    char c = 0;
    while (read(stdout_, &c, 1) == 1 && c != '\n') line += c;
    const size_t colon = line.rfind(':');
    if (colon == std::string::npos || line.find("serving ") != 0) {
      ADD_FAILURE() << "tinbase serve printed: " << line;
      return;
    }
    port_ = std::stoi(line.substr(colon + 1));
  }
  ~ServeChild() {
    if (pid_ > 0) Stop();
    if (stdout_ >= 0) close(stdout_);
  }
  ServeChild(const ServeChild&) = delete;
  ServeChild& operator=(const ServeChild&) = delete;

  int port() const { return port_; }
  // SIGTERM, then reaps it; EXPECTs a clean exit.
  void Stop() {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
    pid_ = -1;
  }

  // SIGKILL, then reaps it; EXPECTs that it died of that signal (not of its own failure first).
  void Kill() {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "status " << status;
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int stdout_ = -1;
  int port_ = 0;
};

}  // namespace tinbase::testing
