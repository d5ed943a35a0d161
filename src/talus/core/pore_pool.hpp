// The pore pool: the state of every interface particle on an interface with pore pressure, one
// record of doubles each at the particle's offset (Particles::pore), in id order over the whole
// case. A record is a header (named by PoreRecord, never indexed by hand), then its band's
// profiles across the interface (BandGrid's state) if its interface has thermal pressurization.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace talus {

// One particle's record, read (const double) or written (double).
template <class T>
class BasicPoreRecord {
public:
  static constexpr std::size_t header = 3;
  explicit BasicPoreRecord(T* at) : at_(at) {}
  T& temperature_rise() const { return at_[0]; } // band-mean temperature rise (K)
  T& pressure_rise() const { return at_[1]; }    // band-mean pore-pressure rise (Pa)
  T& normal_stress() const { return at_[2]; }    // compressive normal stress, recent steps (Pa)
  T* band() const { return at_ + header; }       // the band's profiles (BandGrid's state)

private:
  T* at_;
};
using PoreRecord = BasicPoreRecord<double>;
using ConstPoreRecord = BasicPoreRecord<const double>;

struct PorePool {
  std::vector<double> data;
  // Each record's offset and its interface (fixed for the run: sorting moves only the
  // particles' offsets).
  std::vector<std::pair<std::size_t, int>> entries;

  // Appends a zeroed record of interface f with `band_size` band values; returns its offset.
  std::size_t add(int f, std::size_t band_size) {
    const std::size_t at = data.size();
    entries.emplace_back(at, f);
    data.resize(at + PoreRecord::header + band_size, 0.0);
    return at;
  }
  PoreRecord at(std::int64_t offset) { return PoreRecord(data.data() + offset); }
  ConstPoreRecord at(std::int64_t offset) const { return ConstPoreRecord(data.data() + offset); }
};

} // namespace talus
