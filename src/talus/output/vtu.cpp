#include "talus/output/vtu.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>
#include <stdexcept>
#include <zlib.h>

namespace talus {

bool VtuFields::wants(const std::string& f) const {
  return names.empty() || std::find(names.begin(), names.end(), f) != names.end();
}

namespace {

// A VTK XML UnstructuredGrid of vertices built in two parts: the XML, where each DataArray gives
// its offset into the appended block, and the appended block of raw binary arrays, each
// compressed as VTK's vtkZLibDataCompressor reads it: a UInt64 header (number of blocks, block
// size, size of the last block, then each block's compressed size) followed by the blocks.
class VtuBuilder {
public:
  VtuBuilder(std::size_t n, const std::vector<double>& xyz, bool float32_positions) : n_(n) {
    xml_ = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
           "byte_order=\"LittleEndian\" header_type=\"UInt64\" "
           "compressor=\"vtkZLibDataCompressor\">\n  <UnstructuredGrid>\n";
    xml_ += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
    xml_ += "      <Points>\n";
    if (float32_positions)
      array("Float32", "position", 3, std::vector<float>(xyz.begin(), xyz.end()));
    else
      array("Float64", "position", 3, xyz);
    xml_ += "      </Points>\n      <Cells>\n";
    std::vector<std::int64_t> conn(n), offsets(n);
    std::vector<std::uint8_t> types(n, 1); // VTK_VERTEX
    for (std::size_t p = 0; p < n; ++p)
      conn[p] = static_cast<std::int64_t>(p), offsets[p] = static_cast<std::int64_t>(p + 1);
    array("Int64", "connectivity", 1, conn);
    array("Int64", "offsets", 1, offsets);
    array("UInt8", "types", 1, types);
    xml_ += "      </Cells>\n      <PointData>\n";
  }

  template <class T>
  void array(const char* type, const std::string& name, int components,
             const std::vector<T>& values) {
    xml_ += fmt::format("        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
                        "format=\"appended\" offset=\"{}\"/>\n",
                        type, name, components, appended_.size());
    compress(values.data(), values.size() * sizeof(T));
  }
  // Doubles as Float32 (fields) or Float64.
  void reals(const std::string& name, int components, const std::vector<double>& values,
             bool float64) {
    if (float64)
      array("Float64", name, components, values);
    else
      array("Float32", name, components, std::vector<float>(values.begin(), values.end()));
  }

  std::string finish() {
    xml_ += "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n"
            "  <AppendedData encoding=\"raw\">\n   _";
    xml_ += appended_;
    xml_ += "\n  </AppendedData>\n</VTKFile>\n";
    return std::move(xml_);
  }

private:
  static constexpr std::size_t block = 1 << 20; // uncompressed bytes per block
  void compress(const void* data, std::size_t bytes) {
    const std::size_t blocks = (bytes + block - 1) / block;
    std::vector<std::uint64_t> header = {blocks, block, blocks ? bytes - (blocks - 1) * block : 0};
    std::string body;
    for (std::size_t k = 0; k < blocks; ++k) {
      const std::size_t size = std::min(block, bytes - k * block);
      uLongf out = compressBound(size);
      std::string z(out, '\0');
      if (compress2(reinterpret_cast<Bytef*>(z.data()), &out,
                    static_cast<const Bytef*>(data) + k * block, size, Z_BEST_SPEED) != Z_OK)
        throw std::runtime_error("zlib: compress2 failed");
      z.resize(out);
      header.push_back(out);
      body += z;
    }
    // Zero bytes after the last block's zlib stream (readers stop at the stream's end) make
    // every array's offset but the first 1 mod 4: meshio 5 looks arrays up by offset while it
    // rewrites the offsets to multiples of 4, and an offset equal to a rewritten one made it
    // read the wrong array.
    const std::size_t size = header.size() * sizeof(std::uint64_t) + body.size();
    const std::size_t want = appended_.empty() ? 1 : 0; // this array's size mod 4
    if (blocks > 0) {
      const std::size_t pad = (want + 4 - size % 4) % 4;
      body.append(pad, '\0');
      header.back() += pad;
    }
    appended_.append(reinterpret_cast<const char*>(header.data()),
                     header.size() * sizeof(std::uint64_t));
    appended_ += body;
  }
  std::size_t n_;
  std::string xml_, appended_;
};

} // namespace

template <int D>
std::string particles_to_vtu(const Particles<D>& P, const std::vector<int>& body_material,
                             const VtuFields& fields, const std::vector<ScalarField>& extra) {
  const std::size_t n = P.size();
  auto vec3 = [&](auto get) {
    std::vector<double> a(3 * n, 0.0);
    for (std::size_t p = 0; p < n; ++p)
      for (int d = 0; d < D; ++d)
        a[3 * p + d] = get(p)[d];
    return a;
  };
  VtuBuilder out(n, vec3([&](std::size_t p) { return P.x[p]; }), fields.float32_positions);
  const bool f64 = fields.float64_fields;
  std::vector<std::int32_t> body(n), material(n);
  for (int b = 0; b < P.num_bodies(); ++b)
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
      body[p] = b, material[p] = body_material[b];
  out.array("Int32", "body", 1, body);
  if (fields.wants("material")) out.array("Int32", "material", 1, material);
  out.array("UInt32", "id", 1, P.id);
  if (fields.wants("velocity"))
    out.reals("velocity", 3, vec3([&](std::size_t p) { return P.v[p]; }), f64);
  if (fields.wants("displacement"))
    out.reals("displacement", 3, vec3([&](std::size_t p) { return Vec<D>(P.x[p] - P.x0[p]); }),
              f64);
  if (fields.wants("stress")) {
    // VTK's symmetric tensor order: xx, yy, zz, xy, yz, xz (ours).
    std::vector<double> s(6 * n);
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < 6; ++k)
        s[6 * p + k] = P.stress[p][k];
    out.reals("stress", 6, s, f64);
  }
  if (fields.wants("mass")) out.reals("mass", 1, P.m, f64);
  if (fields.wants("volume")) out.reals("volume", 1, P.vol, f64);
  if (fields.wants("plastic_strain")) out.reals("plastic_strain", 1, P.eps_p, f64);
  if (fields.wants("field")) out.array("Int32", "field", 1, P.field);
  if (fields.wants("interface")) {
    out.array("Int32", "interface", 1, P.iface);
    out.reals("interface_slip", 1, P.slip, f64);
    out.reals("interface_cohesion", 1, P.cohesion, f64);
    out.reals("interface_friction", 1, P.friction, f64);
  }
  for (const auto& [name, values] : extra)
    if (fields.wants(name)) out.reals(name, 1, values, f64);
  return out.finish();
}

std::string vertices_to_vtu(const std::vector<double>& xyz, const std::vector<VtuArray>& arrays) {
  VtuBuilder out(xyz.size() / 3, xyz, false);
  for (const VtuArray& a : arrays) {
    if (!a.f64.empty())
      out.array("Float64", a.name, a.components, a.f64);
    else
      out.array("Int32", a.name, a.components, a.i32);
  }
  return out.finish();
}

std::string pvd_collection(const std::vector<std::pair<double, std::string>>& frames) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
                    "byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [t, file] : frames)
    out += fmt::format("    <DataSet timestep=\"{:.17g}\" part=\"0\" file=\"{}\"/>\n", t, file);
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

template std::string particles_to_vtu<2>(const Particles<2>&, const std::vector<int>&,
                                         const VtuFields&, const std::vector<ScalarField>&);
template std::string particles_to_vtu<3>(const Particles<3>&, const std::vector<int>&,
                                         const VtuFields&, const std::vector<ScalarField>&);

} // namespace talus
