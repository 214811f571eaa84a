#include "pipescope/util/progress.h"

#include <unistd.h>

#include <cstdio>

#include "pipescope/util/logging.h"

namespace pipescope {

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      enabled_(isatty(fileno(stderr)) && CurrentVerbosity() != Verbosity::kQuiet),
      last_draw_(std::chrono::steady_clock::now() - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(std::size_t done) {
  last_done_ = done;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  Draw(done);
}

void ProgressBar::Finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  Draw(last_done_);
  std::fputc('\n', stderr);
}

void ProgressBar::Draw(std::size_t done) {
  constexpr int kWidth = 30;
  if (total_ == 0) {
    std::fprintf(stderr, "\r%s %zu", label_.c_str(), done);
  } else {
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu", label_.c_str(), std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), done, total_);
  }
  std::fflush(stderr);
}

}  // namespace pipescope
