#include "talus/output/vtu.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>

namespace talus {

bool VtuFields::wants(const std::string& f) const {
  return names.empty() || std::find(names.begin(), names.end(), f) != names.end();
}

std::string base64(const void* data, std::size_t bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* in = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes; i += 3) {
    const std::uint32_t a = in[i];
    const std::uint32_t b = i + 1 < bytes ? in[i + 1] : 0;
    const std::uint32_t c = i + 2 < bytes ? in[i + 2] : 0;
    const std::uint32_t t = (a << 16) | (b << 8) | c;
    out += table[(t >> 18) & 63];
    out += table[(t >> 12) & 63];
    out += i + 1 < bytes ? table[(t >> 6) & 63] : '=';
    out += i + 2 < bytes ? table[t & 63] : '=';
  }
  return out;
}

namespace {

// One DataArray in VTK's "binary" encoding: base64 of a UInt64 byte count followed by the data.
template <class T>
void data_array(std::string& out, const char* type, const std::string& name, int components,
                const std::vector<T>& values) {
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::string raw(sizeof(bytes) + bytes, '\0');
  std::memcpy(raw.data(), &bytes, sizeof(bytes));
  if (bytes) std::memcpy(raw.data() + sizeof(bytes), values.data(), bytes);
  out += fmt::format("        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
                     "format=\"binary\">\n          ",
                     type, name, components);
  out += base64(raw.data(), raw.size());
  out += "\n        </DataArray>\n";
}

// The head of a VTU of n vertices at xyz (3 values per point), up to the opening of PointData.
void open_vertices(std::string& out, std::size_t n, const std::vector<double>& xyz) {
  out += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  out += "      <Points>\n";
  data_array(out, "Float64", "position", 3, xyz);
  out += "      </Points>\n      <Cells>\n";
  std::vector<std::int64_t> conn(n), offsets(n);
  std::vector<std::uint8_t> types(n, 1); // VTK_VERTEX
  for (std::size_t p = 0; p < n; ++p)
    conn[p] = static_cast<std::int64_t>(p), offsets[p] = static_cast<std::int64_t>(p + 1);
  data_array(out, "Int64", "connectivity", 1, conn);
  data_array(out, "Int64", "offsets", 1, offsets);
  data_array(out, "UInt8", "types", 1, types);
  out += "      </Cells>\n      <PointData>\n";
}

void close_vertices(std::string& out) {
  out += "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

} // namespace

template <int D>
std::string particles_to_vtu(const Particles<D>& P, const std::vector<int>& body_material,
                             const VtuFields& fields) {
  const std::size_t n = P.size();
  auto vec3 = [&](auto get) {
    std::vector<double> a(3 * n, 0.0);
    for (std::size_t p = 0; p < n; ++p)
      for (int d = 0; d < D; ++d)
        a[3 * p + d] = get(p)[d];
    return a;
  };
  std::string out;
  open_vertices(out, n, vec3([&](std::size_t p) { return P.x[p]; }));

  std::vector<std::int32_t> body(n), material(n);
  for (int b = 0; b < P.num_bodies(); ++b)
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
      body[p] = b, material[p] = body_material[b];
  data_array(out, "Int32", "body", 1, body);
  if (fields.wants("material")) data_array(out, "Int32", "material", 1, material);
  data_array(out, "UInt32", "id", 1, P.id);
  if (fields.wants("velocity"))
    data_array(out, "Float64", "velocity", 3, vec3([&](std::size_t p) { return P.v[p]; }));
  if (fields.wants("displacement"))
    data_array(out, "Float64", "displacement", 3,
               vec3([&](std::size_t p) { return Vec<D>(P.x[p] - P.x0[p]); }));
  if (fields.wants("stress")) {
    // VTK's symmetric tensor order: xx, yy, zz, xy, yz, xz (ours).
    std::vector<double> s(6 * n);
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < 6; ++k)
        s[6 * p + k] = P.stress[p][k];
    data_array(out, "Float64", "stress", 6, s);
  }
  if (fields.wants("mass")) data_array(out, "Float64", "mass", 1, P.m);
  if (fields.wants("volume")) data_array(out, "Float64", "volume", 1, P.vol);
  if (fields.wants("plastic_strain")) data_array(out, "Float64", "plastic_strain", 1, P.eps_p);
  if (fields.wants("field")) data_array(out, "Int32", "field", 1, P.field);
  if (fields.wants("interface")) {
    data_array(out, "Int32", "interface", 1, P.iface);
    data_array(out, "Float64", "interface_slip", 1, P.slip);
    data_array(out, "Float64", "interface_cohesion", 1, P.cohesion);
    data_array(out, "Float64", "interface_friction", 1, P.friction);
  }
  close_vertices(out);
  return out;
}

std::string vertices_to_vtu(const std::vector<double>& xyz, const std::vector<VtuArray>& arrays) {
  std::string out;
  open_vertices(out, xyz.size() / 3, xyz);
  for (const VtuArray& a : arrays) {
    if (!a.f64.empty())
      data_array(out, "Float64", a.name, a.components, a.f64);
    else
      data_array(out, "Int32", a.name, a.components, a.i32);
  }
  close_vertices(out);
  return out;
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
                                         const VtuFields&);
template std::string particles_to_vtu<3>(const Particles<3>&, const std::vector<int>&,
                                         const VtuFields&);

} // namespace talus
