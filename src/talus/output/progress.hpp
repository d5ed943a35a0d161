// The run's progress: a bar on a terminal, a plain line every 10 % or 30 s otherwise.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fmt/format.h>
#include <ostream>
#include <string>
#include <unistd.h>

namespace talus {

// A progress bar on a terminal; a plain line every 10 % or 30 s otherwise.
class Progress {
public:
  Progress(std::ostream* out, double end_time, std::int64_t first_step)
      : out_(out), end_(end_time), tty_(out && ::isatty(STDOUT_FILENO)),
        start_(std::chrono::steady_clock::now()), first_step_(first_step) {}

  void update(double t, std::int64_t steps, bool final = false) {
    if (!out_) return;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double frac = std::min(1.0, t / end_);
    if (first_frac_ < 0) first_frac_ = frac; // a restarted run starts part-way
    const bool due =
        tty_ ? wall - last_wall_ >= 0.2 : (frac >= next_frac_ || wall - last_wall_ >= 30.0);
    if (!due && !final) return;
    if (final && !tty_ && steps == last_steps_) return; // this state is already on its own line
    last_wall_ = wall;
    last_steps_ = steps;
    while (next_frac_ <= frac)
      next_frac_ += 0.1;
    const double rate = wall > 0 ? static_cast<double>(steps - first_step_) / wall : 0.0;
    const double eta = frac > first_frac_ ? wall * (1.0 - frac) / (frac - first_frac_) : 0.0;
    const std::string text =
        fmt::format("t = {:.4g} / {:.4g} s  {:5.1f} %  {} steps  {:.0f} steps/s  ETA {:.0f} s", t,
                    end_, 100.0 * frac, steps, rate, eta);
    if (tty_) {
      const int width = 30;
      const int filled = static_cast<int>(frac * width);
      *out_ << "\r[" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << text
            << (final ? "\n" : "") << std::flush;
    } else {
      *out_ << text << "\n" << std::flush;
    }
  }

private:
  std::ostream* out_;
  double end_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  double last_wall_ = -1e9;
  double next_frac_ = 0.0;
  std::int64_t first_step_;
  double first_frac_ = -1.0;
  std::int64_t last_steps_ = -1;
};

} // namespace talus
