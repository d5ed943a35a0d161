#include "talus/output/run_writer.hpp"

#include "talus/case/size.hpp"
#include "talus/output/files.hpp"
#include "talus/output/frame_totals.hpp"
#include "talus/output/vtu.hpp"
#include "talus/solver/diagnostics.hpp"
#include "talus/version.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <sys/stat.h>

namespace talus {

namespace {

// A text cell as RFC 4180 writes it: quoted (with quotes doubled) if it holds a comma, a quote
// or a line break, as is otherwise.
std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char ch : s)
    q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

template <int D>
std::string components(const char* prefix, const char* suffix = "") {
  std::string s;
  for (int d = 0; d < D; ++d)
    s += fmt::format(",{}{}{}", prefix, "xyz"[d], suffix);
  return s;
}

template <int D>
std::string join(const Vec<D>& v) {
  std::string s;
  for (int d = 0; d < D; ++d)
    s += fmt::format(",{:.10g}", v[d]);
  return s;
}

// One vertex per (node, corrected body): the body and the other body there, the force on the
// body (N; per metre in 2D), its outward normal, and the frictional and cohesive resistance used.
template <int D>
std::string contact_nodes_to_vtu(const std::vector<ContactNodeForce<D>>& nodes) {
  const std::size_t n = nodes.size();
  std::vector<double> xyz(3 * n, 0.0);
  VtuArray body{"body", 1, {}, {}}, other{"other", 1, {}, {}};
  VtuArray force{"force", 3, std::vector<double>(3 * n, 0.0), {}};
  VtuArray normal{"normal", 3, std::vector<double>(3 * n, 0.0), {}};
  VtuArray frictional{"frictional_force", 1, {}, {}}, cohesive{"cohesive_force", 1, {}, {}};
  for (std::size_t i = 0; i < n; ++i) {
    const ContactNodeForce<D>& c = nodes[i];
    for (int d = 0; d < D; ++d) {
      xyz[3 * i + d] = c.position[d];
      force.f64[3 * i + d] = c.force[d];
      normal.f64[3 * i + d] = c.normal[d];
    }
    body.i32.push_back(c.body);
    other.i32.push_back(c.other);
    frictional.f64.push_back(c.frictional);
    cohesive.f64.push_back(c.cohesive);
  }
  return vertices_to_vtu(xyz, {body, other, force, normal, frictional, cohesive});
}

// legend.json: ParaView colour-map presets (Color Map Editor, "Import Presets") that name the
// values of the frames' `body` and `material` arrays: interpret them as categories and each
// particle shows its body's or material's name.
std::string legend_presets(const Case& c) {
  auto preset = [](const std::string& name, const std::vector<std::string>& labels) {
    nlohmann::json annotations = nlohmann::json::array(), colors = nlohmann::json::array();
    // matplotlib's tab10, the colours of tools/plot_run.py's body snapshots.
    static const double tab10[10][3] = {
        {0.122, 0.467, 0.706}, {1.0, 0.498, 0.055},   {0.173, 0.627, 0.173}, {0.839, 0.153, 0.157},
        {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294}, {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498},
        {0.737, 0.741, 0.133}, {0.090, 0.745, 0.812}};
    for (std::size_t i = 0; i < labels.size(); ++i) {
      annotations.push_back(std::to_string(i));
      annotations.push_back(labels[i]);
      for (const double v : tab10[i % 10])
        colors.push_back(v);
    }
    return nlohmann::json{{"Name", name}, {"Annotations", annotations}, {"IndexedColors", colors}};
  };
  std::vector<std::string> bodies, materials;
  for (const BodySpec& b : c.bodies)
    bodies.push_back(b.name);
  for (const Material& m : c.materials)
    materials.push_back(m.name);
  return nlohmann::json::array({preset("talus bodies: " + c.title, bodies),
                                preset("talus materials: " + c.title, materials)})
             .dump(2) +
         "\n";
}

} // namespace

template <int D>
RunWriter<D>::RunWriter(std::string dir, const Simulation<D>& sim,
                        std::vector<std::uint32_t> probe_ids)
    : dir_(std::move(dir)), split_(!frame_parts(sim).fixed.empty()),
      probe_ids_(std::move(probe_ids)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec)
    throw OutputError(fmt::format("{}: cannot create the run folder: {}", dir_, ec.message()));
  write_file_atomic(dir_ + "/case.toml", sim.case_().text);
  write_file_atomic(dir_ + "/case_as_run.toml",
                    "# The case as talus read it: case.toml with its [[run]] --set values applied, "
                    "for tools to read.\n# To run the case again, run case.toml.\n" +
                        sim.case_().resolved);
  write_file_atomic(dir_ + "/legend.json", legend_presets(sim.case_()));
  energy_ = "time,step,dt,kinetic_energy" + components<D>("momentum_") + "\n";
  bodies_ = "time,body,mass" + components<D>("centroid_") + components<D>("velocity_") +
            ",mean_speed,max_speed,kinetic_energy,gravity_work,contact_work,internal_work,"
            "strain_energy,orphans\n";
  contacts_ = "time,body,other" + components<D>("force_") + "\n";
  interfaces_ = "time,interface,cohesive_force,frictional_force,normal_force";
  // With pore pressure on an interface: its particles' excess pore pressure (Pa) and, with a
  // band, its temperature (deg C), area means and largest (empty for an interface without).
  if (sim.setup().pore_pressure) interfaces_ += ",pore_pressure_mean,pore_pressure_max";
  if (sim.setup().heating) interfaces_ += ",temperature_mean,temperature_max";
  interfaces_ += "\n";
  probes_ = "time,probe" + components<D>("") + components<D>("velocity_") + ",speed,displacement\n";
  waves_ = "time,gauge,elevation\n";
}

template <int D>
void RunWriter<D>::write_rows(const Simulation<D>& sim, const FrameTotals<D>& totals) {
  const Case& c = sim.case_();
  const double t = sim.time();
  const int B = sim.num_bodies();
  for (int b = 0; b < B; ++b) {
    const BodyTotals<D>& T = totals.bodies[b];
    bodies_ +=
        fmt::format("{:.10g},{},{:.10g}{}{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},"
                    "{:.10g},{}\n",
                    t, csv_text(c.bodies[b].name), T.mass, join<D>(T.centroid), join<D>(T.velocity),
                    T.mean_speed, T.max_speed, T.kinetic_energy, T.gravity_work,
                    sim.contact_record().work[b], sim.internal_work(b), T.strain_energy, T.orphans);
  }
  energy_ += fmt::format("{:.10g},{},{:.10g},{:.10g}{}\n", t, sim.steps(), sim.last_dt(),
                         totals.kinetic_energy, join<D>(totals.momentum));
  for (int a = 0; a < B; ++a)
    for (int b = 0; b < B; ++b)
      if (a != b && !sim.contact_record().mean_force(a, b).isZero())
        contacts_ +=
            fmt::format("{:.10g},{},{}{}\n", t, csv_text(c.bodies[a].name),
                        csv_text(c.bodies[b].name), join<D>(sim.contact_record().mean_force(a, b)));
  for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
    const InterfaceForce F = sim.contact_record().mean_interface_force(f);
    interfaces_ += fmt::format(
        "{:.10g},{},{:.10g},{:.10g},{:.10g}", t,
        csv_text(c.bodies[c.interfaces[f].a].name + "-" + c.bodies[c.interfaces[f].b].name),
        F.cohesive, F.frictional, F.normal);
    const bool own = sim.setup().interface_pressure[f], band = sim.setup().bands[f].has_value();
    const InterfaceWater& water = totals.water[f];
    if (sim.setup().pore_pressure)
      interfaces_ += own ? fmt::format(",{:.10g},{:.10g}", water.pressure_mean, water.pressure_max)
                         : std::string(",,");
    if (sim.setup().heating)
      interfaces_ +=
          band ? fmt::format(",{:.10g},{:.10g}", water.temperature_mean, water.temperature_max)
               : std::string(",,");
    interfaces_ += "\n";
  }
  for (std::size_t k = 0; k < c.gauges.size(); ++k) // the surface's elevation; empty: dry
    waves_ += fmt::format("{:.10g},{},{}\n", t, csv_text(c.gauges[k].name),
                          std::isnan(totals.gauges[k]) ? std::string()
                                                       : fmt::format("{:.10g}", totals.gauges[k]));
  for (std::size_t k = 0; k < probe_ids_.size(); ++k) {
    const ProbeState<D>& pr = totals.probes[k];
    probes_ += fmt::format("{:.10g},{}{}{},{:.10g},{:.10g}\n", t, csv_text(c.probes[k].name),
                           join<D>(pr.x), join<D>(pr.v), pr.v.norm(), (pr.x - pr.x0).norm());
  }
}

template <int D>
typename RunWriter<D>::FrameParts RunWriter<D>::frame_parts(const Simulation<D>& sim) {
  FrameParts parts;
  std::size_t at = 0;
  for (int b = 0; b < sim.num_bodies(); ++b) {
    const std::size_t end = at + sim.body_particles(b);
    auto& spans = sim.setup().bodies[b].fixed ? parts.fixed : parts.moving;
    if (end > at) {
      if (!spans.empty() && spans.back().second == at)
        spans.back().second = end; // bodies side by side: one span
      else
        spans.emplace_back(at, end);
    }
    at = end;
  }
  if (parts.moving.empty() || parts.fixed.empty()) parts = FrameParts{{{0, at}}, {}};
  return parts;
}

template <int D>
std::string RunWriter<D>::next_particle_frame() const {
  return dir_ + "/" + fmt::format("particles_{:06d}.vtu", frames_.size());
}

namespace {
// The frames' fields and precision, as the case's [output] asks.
VtuFields frame_fields(const Case& c) {
  VtuFields f{c.output.fields, c.output.float64_fields, frame_float32_positions(c)};
  f.field_bits = c.output.field_bits;
  f.position_quantum = frame_position_quantum(c);
  f.compression = c.output.zlib_frames ? FrameCompression::zlib : FrameCompression::lzma;
  return f;
}
} // namespace

template <int D>
void RunWriter<D>::write_particles(const std::string& path, const Simulation<D>& sim,
                                   ParticleOrder& order, const ParticleOrder::Spans& spans) {
  const Case& c = sim.case_();
  std::vector<int> mats;
  for (const BodySpec& b : c.bodies)
    mats.push_back(b.material);
  // With water: each particle's pore pressure; with bands: their temperature (NaN elsewhere).
  std::vector<ScalarField> extra;
  if (sim.setup().water.on || sim.setup().pore_pressure)
    extra.emplace_back("pore_pressure", [&](std::size_t p) { return pore_pressure(sim, p); });
  if (sim.setup().heating)
    extra.emplace_back("band_temperature", [&](std::size_t p) { return band_temperature(sim, p); });
  write_particles_vtu<D>(path, sim.particles(), mats, frame_fields(c), extra, order, spans);
}

template <int D>
void RunWriter<D>::write_frame(const Simulation<D>& sim, const FrameTotals<D>& totals,
                               const std::vector<ContactNodeForce<D>>& contact_nodes) {
  write_rows(sim, totals);
  const Case& c = sim.case_();
  const double t = sim.time();
  if (c.output.particles)
    frames_.emplace_back(t, fmt::format("particles_{:06d}.vtu", frames_.size()));
  if (c.output.contact_nodes) {
    const std::string name = fmt::format("contact_nodes_{:06d}.vtu", contact_frames_.size());
    write_file_atomic(dir_ + "/" + name, contact_nodes_to_vtu<D>(contact_nodes));
    contact_frames_.emplace_back(t, name);
  }
  write_tables(sim);
}

template <int D>
std::vector<std::string> RunWriter<D>::missing_frames() const {
  std::vector<std::string> missing;
  std::error_code ec;
  if (split_ && !frames_.empty() && !std::filesystem::is_regular_file(dir_ + "/" + fixed_part, ec))
    missing.emplace_back(fixed_part);
  for (const auto* list : {&frames_, &contact_frames_})
    for (const auto& [t, name] : *list) {
      if (!std::filesystem::is_regular_file(dir_ + "/" + name, ec)) missing.push_back(name);
    }
  return missing;
}

template <int D>
void RunWriter<D>::write_tables(const Simulation<D>& sim) const {
  const Case& c = sim.case_();
  const int B = sim.num_bodies();
  if (c.output.particles)
    write_file_atomic(dir_ + "/particles.pvd",
                      pvd_collection(frames_, split_ ? fixed_part : std::string()));
  if (c.output.contact_nodes)
    write_file_atomic(dir_ + "/contact_nodes.pvd", pvd_collection(contact_frames_));
  write_file_atomic(dir_ + "/energy.csv", energy_);
  write_file_atomic(dir_ + "/bodies.csv", bodies_);
  if (!probe_ids_.empty()) write_file_atomic(dir_ + "/probes.csv", probes_);
  if (!c.gauges.empty()) write_file_atomic(dir_ + "/waves.csv", waves_);
  if (B > 1) write_file_atomic(dir_ + "/contacts.csv", contacts_);
  if (!c.interfaces.empty()) write_file_atomic(dir_ + "/interfaces.csv", interfaces_);
}

template <int D>
void RunWriter<D>::write_summary(const Simulation<D>& sim, const std::string& status,
                                 double wall_seconds, double stepping_seconds, int threads,
                                 const std::string& message, const nlohmann::json& results) {
  const Case& c = sim.case_();
  const std::size_t particles = sim.case_particles();
  nlohmann::json j;
  j["talus_version"] = version;
  j["case"] = c.file;
  j["title"] = c.title;
  j["dimension"] = D;
  j["particles"] = particles;
  j["nodes"] = sim.grid().num_nodes();
  nlohmann::json bodies = nlohmann::json::object();
  for (int b = 0; b < sim.num_bodies(); ++b)
    bodies[c.bodies[b].name] = {{"particles", sim.body_particles(b)},
                                {"material", c.materials[c.bodies[b].material].name}};
  j["bodies"] = bodies;
  j["steps"] = sim.steps();
  j["simulated_time"] = sim.time();
  j["wall_seconds"] = wall_seconds;
  j["stepping_seconds"] = stepping_seconds;
  j["particle_updates_per_second"] =
      stepping_seconds > 0
          ? static_cast<double>(particles) * static_cast<double>(sim.steps()) / stepping_seconds
          : 0.0;
  j["threads"] = threads;
  j["status"] = status;
  if (!message.empty()) j["message"] = message;
  j["results"] = results;
  write_file_atomic(dir_ + "/summary.json", j.dump(2) + "\n");
}

RunFolder prepare_run_inputs(const Case& c, const std::string& dir, bool overwrite) {
  std::vector<std::string> inputs;
  std::vector<unsigned> modes;
  for (const InputFile& f : c.inputs) {
    std::ifstream in(f.source, std::ios::binary);
    if (!in) throw OutputError(fmt::format("{}: cannot read the case's input file", f.source));
    inputs.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    struct stat st {};
    modes.push_back(::stat(f.source.c_str(), &st) == 0 ? st.st_mode & 07777u : 0644u);
  }
  RunFolder folder(dir, overwrite ? RunFolder::Use::overwrite : RunFolder::Use::fresh);
  // case.toml first: it names the copies, so that a run stopped among them leaves a folder of
  // talus's files alone (foreign_entries), which --overwrite or a sweep's resume may empty.
  write_file_atomic(dir + "/case.toml", c.text);
  if (!c.inputs.empty()) make_folder(dir + "/inputs");
  for (std::size_t i = 0; i < c.inputs.size(); ++i) {
    AtomicFile copy(dir + "/" + c.inputs[i].copy, modes[i]);
    copy.write(inputs[i]);
    copy.commit();
  }
  return folder;
}

template class RunWriter<2>;
template class RunWriter<3>;

} // namespace talus
