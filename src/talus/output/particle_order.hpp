// Per-particle values gathered in one process's particle order, for output that must not need
// the whole state in one place (vtu.hpp's frames).
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace talus {

// Per-particle values in one process's particle order, chunk by chunk: on one process the
// particles as they stand (LocalOrder); on several, each process's own particles gathered to
// rank 0 in that order (Distributed).
class ParticleOrder {
public:
  using Fill = std::function<void(std::size_t p, char* out)>; // particle p's `width` bytes
  using Take = std::function<void(const char* data, std::size_t count)>;
  // Runs [begin, end) of the order's indices, ascending and disjoint (a body's particles are one
  // run: Particles::body_begin).
  using Spans = std::vector<std::pair<std::size_t, std::size_t>>;
  virtual ~ParticleOrder() = default;
  virtual std::size_t total() const = 0; // the whole case's particles
  virtual bool receives() const = 0;     // whether take() is called on this process
  // Collective: fill() for each of this process's own particles in `spans`; take() where
  // receives(), with the values of consecutive runs of them, all of them in order.
  virtual void gather(std::size_t width, const Fill& fill, const Take& take,
                      const Spans& spans) = 0;
  // Collective: f(p) for each of this process's own particles p in `spans` (the p that
  // gather's fill sees), then each value of `largest` replaced by its largest over the processes.
  virtual void reduce_max(const Spans& spans, const std::function<void(std::size_t p)>& f,
                          std::vector<double>& largest) = 0;
  // The same over every particle.
  void gather(std::size_t width, const Fill& fill, const Take& take) {
    gather(width, fill, take, Spans{{0, total()}});
  }
  static std::size_t count(const Spans& spans) {
    std::size_t n = 0;
    for (const auto& [begin, end] : spans)
      n += end - begin;
    return n;
  }
};

// One process: particles [0, n) in their order.
class LocalOrder final : public ParticleOrder {
public:
  explicit LocalOrder(std::size_t n) : n_(n) {}
  std::size_t total() const override { return n_; }
  bool receives() const override { return true; }
  using ParticleOrder::gather;
  void gather(std::size_t width, const Fill& fill, const Take& take, const Spans& spans) override {
    const std::size_t chunk = std::clamp<std::size_t>(
        (std::size_t{4} << 20) / std::max<std::size_t>(width, 1), 1, std::max<std::size_t>(n_, 1));
    std::vector<char> buf(chunk * width);
    for (const auto& [begin, end] : spans)
      for (std::size_t at = begin; at < end; at += chunk) {
        const std::size_t count = std::min(chunk, end - at);
        for (std::size_t k = 0; k < count; ++k)
          fill(at + k, buf.data() + k * width);
        take(buf.data(), count);
      }
  }
  void reduce_max(const Spans& spans, const std::function<void(std::size_t p)>& f,
                  std::vector<double>&) override {
    for (const auto& [begin, end] : spans)
      for (std::size_t p = begin; p < end; ++p)
        f(p);
  }

private:
  std::size_t n_;
};

} // namespace talus
