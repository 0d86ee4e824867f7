// A world's description as bytes and back (world_state.hpp). One function, visit(), walks every value of a
// description for both directions, so that what is written and what is read cannot drift apart.
#include "world_state.hpp"

#include "pbd/constraint_types.hpp"
#include "pbd/error.hpp"

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace pbd::python {

namespace {

constexpr char kTag[8] = {'p', 'b', 'd', 'w', 'o', 'r', 'l', 'd'};
constexpr std::uint32_t kFormat = 1;  // raise when visit() changes

/// Appends values to a byte string.
struct Writer {
  std::string bytes;
  static constexpr bool kReading = false;
  template <class T> void raw(T& v) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void count(std::size_t n, std::size_t) {
    std::uint64_t c = n;
    raw(c);
  }
};

/// Reads values back, refusing to read past the end.
struct Reader {
  std::string_view bytes;
  static constexpr bool kReading = true;
  template <class T> void raw(T& v) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    if (bytes.size() < sizeof(T)) throw Error("pickled world: the data ends too early (truncated or not a pbd world)");
    std::memcpy(&v, bytes.data(), sizeof(T));
    bytes.remove_prefix(sizeof(T));
  }
  /// A count of items of at least `item_bytes` each: no more than the bytes left could hold.
  std::size_t count(std::size_t, std::size_t item_bytes) {
    std::uint64_t c = 0;
    raw(c);
    if (item_bytes && c > bytes.size() / item_bytes)
      throw Error("pickled world: a count of " + std::to_string(c) + " items exceeds the data left");
    return std::size_t(c);
  }
};

template <class A> std::size_t visit_count(A& a, std::size_t n, std::size_t item_bytes) {
  if constexpr (A::kReading) return a.count(n, item_bytes);
  else {
    a.count(n, item_bytes);
    return n;
  }
}

template <class A, class T> void visit(A& a, T& v) requires(std::is_arithmetic_v<T> || std::is_enum_v<T>) { a.raw(v); }

template <class A, class T, int R> void visit(A& a, Eigen::Matrix<T, R, 1>& v) requires(R > 0) {
  for (int i = 0; i < R; ++i) a.raw(v[i]);
}

template <class A, class T, std::size_t K> void visit(A& a, std::array<T, K>& v) {
  for (T& x : v) visit(a, x);
}

template <class A> void visit(A& a, Matrix3X<double>& m) {
  const std::size_t n = visit_count(a, std::size_t(m.cols()), 3 * sizeof(double));
  if constexpr (A::kReading) m.resize(3, Eigen::Index(n));
  for (Eigen::Index i = 0; i < m.size(); ++i) a.raw(m.data()[i]);
}

template <class A> void visit(A& a, VectorX<double>& v) {
  const std::size_t n = visit_count(a, std::size_t(v.size()), sizeof(double));
  if constexpr (A::kReading) v.resize(Eigen::Index(n));
  for (Eigen::Index i = 0; i < v.size(); ++i) a.raw(v[i]);
}

template <class A, class T> void visit(A& a, std::vector<T>& v) {
  const std::size_t n = visit_count(a, v.size(), 1);
  if constexpr (A::kReading) v.resize(n);
  for (T& x : v) visit(a, x);
}

template <class A> void visit(A& a, Material& m) {
  visit(a, m.stiffness), visit(a, m.toe_strain), visit(a, m.yield_strain), visit(a, m.hardening);
  visit(a, m.rupture_strain);
}
template <class A> void visit(A& a, Stiffness& s) { visit(a, s.mode), visit(a, s.k), visit(a, s.compliance), visit(a, s.material); }
template <class A> void visit(A& a, ContactMaterial<double>& m) {
  visit(a, m.static_friction), visit(a, m.kinetic_friction), visit(a, m.restitution);
}
template <class A> void visit(A& a, PressureSchedule& p) { visit(a, p.from), visit(a, p.to), visit(a, p.duration); }
template <class A> void visit(A& a, VolumeDescription& v) {
  visit(a, v.triangles), visit(a, v.set), visit(a, v.rest), visit(a, v.pressure);
}
template <class A> void visit(A& a, SurfaceDescription& s) { visit(a, s.triangles), visit(a, s.cut); }
template <class A> void visit(A& a, PlaneDescription& p) {
  Vec3<double> n = p.normal;
  visit(a, n), visit(a, p.offset), visit(a, p.material);
  p.normal = n;
}
template <class A> void visit(A& a, SphereDescription& s) {
  Vec3<double> c = s.center;
  visit(a, c), visit(a, s.radius), visit(a, s.material);
  s.center = c;
}
template <class A> void visit(A& a, ContactBody<double>& b) {
  visit(a, b.first), visit(a, b.count), visit(a, b.radius), visit(a, b.material), visit(a, b.self_collision);
  visit(a, b.interior);
}
template <class A> void visit(A& a, StepParams<double>& p) {
  visit(a, p.dt), visit(a, p.substeps), visit(a, p.iterations), visit(a, p.gravity), visit(a, p.damping);
  visit(a, p.collision_margin), visit(a, p.solver), visit(a, p.jacobi_omega), visit(a, p.sweep_order);
  auto& c = p.chebyshev;
  visit(a, c.enabled), visit(a, c.rho), visit(a, c.delay), visit(a, c.max_rho), visit(a, c.diverge);
  auto& h = p.hierarchy;
  visit(a, h.enabled), visit(a, h.levels), visit(a, h.parents), visit(a, h.sweeps), visit(a, h.slack), visit(a, h.compliant);
}
template <class A> void visit(A& a, BlockOptions& b) {
  std::uint64_t n = b.constraints_per_block;
  visit(a, n), visit(a, b.use_metis);
  b.constraints_per_block = std::size_t(n);
}

/// A built-in constraint: its particles, its set, its rest values (fields()) and what else it holds (a tether's pin).
template <class A, class C> void visit_constraint(A& a, C& c) {
  visit(a, c.particles), visit(a, c.set);
  for_each_field<C>([&](const auto& field, auto) { visit(a, c.*field.member); });
  if constexpr (requires { c.pin; }) visit(a, c.pin);
}

template <class A> void visit(A& a, WorldDescription& d) {
  visit(a, d.positions), visit(a, d.velocities), visit(a, d.inverse_masses), visit(a, d.sets);
  std::apply([&](auto&... lists) {
    auto one = [&](auto& list) {
      const std::size_t n = visit_count(a, list.size(), sizeof(Index));
      if constexpr (A::kReading) list.resize(n);
      for (auto& c : list) visit_constraint(a, c);
    };
    (one(lists), ...);
  }, d.constraint_lists);
  visit(a, d.volumes), visit(a, d.surfaces), visit(a, d.planes), visit(a, d.spheres), visit(a, d.contact_bodies);
  visit(a, d.params), visit(a, d.blocking);
}

}  // namespace

std::string save_description(const WorldDescription& description) {
  Writer w;
  w.bytes.append(kTag, sizeof kTag);
  std::uint32_t format = kFormat;
  w.raw(format);
  WorldDescription d = description;  // visit() takes its argument mutable for both directions
  visit(w, d);
  return std::move(w.bytes);
}

WorldDescription load_description(std::string_view bytes) {
  if (bytes.size() < sizeof kTag || std::memcmp(bytes.data(), kTag, sizeof kTag) != 0)
    throw Error("pickled world: not the state of a pbd World (its tag is missing)");
  Reader r{bytes.substr(sizeof kTag)};
  std::uint32_t format = 0;
  r.raw(format);
  if (format != kFormat)
    throw Error("pickled world: format " + std::to_string(format) + ", this pbd reads format " + std::to_string(kFormat));
  WorldDescription d;
  visit(r, d);
  if (!r.bytes.empty()) throw Error("pickled world: " + std::to_string(r.bytes.size()) + " bytes left over after the world");
  return d;
}

}  // namespace pbd::python
