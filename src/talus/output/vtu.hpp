// ParaView output: particles as VTK XML UnstructuredGrid (.vtu: appended raw binary arrays,
// LZMA- or zlib-compressed as VTK's own compressors write them) and the time series that lists them
// (.pvd). The writer reads the state; the solver knows no format.
#pragma once

#include "talus/core/particles.hpp"
#include "talus/output/particle_order.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace talus {

// How a frame's arrays are compressed (output.compression): LZMA (xz, VTK's
// vtkLZMADataCompressor) or zlib (vtkZLibDataCompressor).
enum class FrameCompression { lzma, zlib };

// The particle fields a frame carries (positions and body id always).
struct VtuFields {
  std::vector<std::string> names; // empty: all
  bool float64_fields = false;    // output.precision = "float64": fields in double precision
  bool float32_positions = false; // output.position_precision = "float32"
  // output.field_bits: each real field's values rounded to a multiple of a power of two q_b per
  // body b, q_b <= 2^-field_bits of the body's largest magnitude in the array (0: exact).
  int field_bits = 0;
  // Positions rounded to a multiple of this power of two (0: exact).
  double position_quantum = 0.0;
  FrameCompression compression = FrameCompression::lzma;
  bool wants(const std::string& f) const;
};

// A per-particle scalar the simulation derives (pore pressure, band temperature): its name and
// its value at particle p.
using ScalarField = std::pair<std::string, std::function<double(std::size_t)>>;

// The frame of P's particles in memory (one process): those in `spans` (empty: all).
template <int D>
std::string particles_to_vtu(const Particles<D>& P, const std::vector<int>& body_material,
                             const VtuFields& fields, const std::vector<ScalarField>& extra = {},
                             const ParticleOrder::Spans& spans = {});

// The frame of the particles in `spans` of `order`'s order written to `path` chunk by chunk,
// with no more than a few blocks of it in memory: collective, P being this process's particles
// (on several processes, with ghosts that order's fill skips). Where order.receives(), the file
// is written atomically; a failure there throws OutputError after every process has taken part.
template <int D>
void write_particles_vtu(const std::string& path, const Particles<D>& P,
                         const std::vector<int>& body_material, const VtuFields& fields,
                         const std::vector<ScalarField>& extra, ParticleOrder& order,
                         const ParticleOrder::Spans& spans);

// Any point set as VTU vertices (zlib-compressed): positions (x, y, z per point) and named point
// arrays, each
// Float64 (f64, if not empty) or Int32 (i32), `components` values per point.
struct VtuArray {
  std::string name;
  int components = 1;
  std::vector<double> f64;
  std::vector<std::int32_t> i32;
};
std::string vertices_to_vtu(const std::vector<double>& xyz, const std::vector<VtuArray>& arrays);

// A .pvd collection of (time, file name) frames; `fixed`, if not empty, is a second part listed
// at every time (the particles that never change, written once).
std::string pvd_collection(const std::vector<std::pair<double, std::string>>& frames,
                           const std::string& fixed = {});

} // namespace talus
