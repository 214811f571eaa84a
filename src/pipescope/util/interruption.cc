#include "pipescope/util/interruption.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <iostream>
#include <mutex>
#include <set>
#include <thread>

namespace pipescope {
namespace {

// A recursive mutex: WithoutInterruption() steps may register and release paths themselves.
std::recursive_mutex& Mutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

std::multiset<std::filesystem::path>& Registered() {
  static std::multiset<std::filesystem::path> paths;
  return paths;
}

// The run's other threads keep writing until _exit: a file created in a folder after
// remove_all listed it makes the folder's own removal fail, so remove until it is gone.
void RemoveWhileOthersWrite(const std::filesystem::path& path) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
    if (!std::filesystem::exists(path, ignored)) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void WaitForSignals(sigset_t signals) {
  int signal_number = 0;
  if (sigwait(&signals, &signal_number) != 0) return;
  std::lock_guard<std::recursive_mutex> lock(Mutex());
  const char* name = signal_number == SIGINT   ? "SIGINT"
                     : signal_number == SIGHUP ? "SIGHUP"
                                               : "SIGTERM";
  std::cerr << "\npipescope: interrupted (" << name << ")";
  for (const std::filesystem::path& path : Registered()) {
    RemoveWhileOthersWrite(path);
    std::cerr << "; removed " << path.string();
  }
  std::cerr << "; outputs already in place are whole, nothing half-written is left" << std::endl;
  _exit(128 + signal_number);
}

}  // namespace

void InstallInterruptionHandler() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGHUP);  // the terminal closed
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread(WaitForSignals, signals).detach();
}

RemoveOnInterruption::RemoveOnInterruption(std::filesystem::path path) : path_(std::move(path)) {
  std::lock_guard<std::recursive_mutex> lock(Mutex());
  Registered().insert(path_);
  registered_ = true;
}

RemoveOnInterruption::~RemoveOnInterruption() { Release(); }

void RemoveOnInterruption::Release() {
  std::lock_guard<std::recursive_mutex> lock(Mutex());
  if (!registered_) return;
  const auto it = Registered().find(path_);
  if (it != Registered().end()) Registered().erase(it);
  registered_ = false;
}

namespace interruption_internal {
void Lock() { Mutex().lock(); }
void Unlock() { Mutex().unlock(); }
}  // namespace interruption_internal

}  // namespace pipescope
