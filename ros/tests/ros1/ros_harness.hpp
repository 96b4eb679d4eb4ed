#pragma once
// What the ROS tests need around them: a real roscore on a free port (its
// ROS_MASTER_URI set in this test process only), child processes started
// and ended by their id, and waiting on a condition with a deadline
// instead of sleeping a fixed time.
#include <sys/types.h>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace stridemap::ros_test {

/// A child process in its own process group; the destructor ends the group
/// (SIGINT, then SIGKILL after a grace period) and reaps it.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const std::string& log_path);
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  /// False once the process has exited; `status` then says how.
  bool running();
  int exit_status() const { return status_; }
  /// Ends the process group and waits for it (at most `grace_s`, then SIGKILL).
  void stop(double grace_s = 10.0);

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool reaped_ = false;
};

/// A TCP port nobody listens on now.
int free_port();

/// Polls `done` every few milliseconds (calling `pump` between polls) until
/// it holds or `timeout_s` passes; returns whether it held.
bool wait_for(const std::function<bool()>& done, double timeout_s, const std::function<void()>& pump = {});

/// A fresh folder under the build's temporary space.
std::string temp_folder(const std::string& name);

/// The whole of a file (for failure messages).
std::string read_text(const std::string& path);

}  // namespace stridemap::ros_test
