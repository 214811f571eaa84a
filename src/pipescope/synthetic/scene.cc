#include "pipescope/synthetic/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pipescope {
namespace {

using Eigen::Vector3d;
using internal::SectionGeometry;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2 * std::numbers::pi;
// Scenes up to this many sections are intersected with stack buffers only.
constexpr int kInlineSections = 64;
// Bracketed Newton stops when its step falls below this (metres): well under the 1e-12 m the
// renderer's ground truth needs, and above rounding of coordinates of a few metres.
constexpr double kRootTolerance = 1e-14;
// Axis directions closer than this (sine of the angle) to world X take +Y as default reference.
constexpr double kAlongXSine = 1e-3;

// A crossing of a section's boundary: its wall, or the disc closing one of its ends.
struct Event {
  double t;
  bool wall;
};

Vector3d DefaultReference(const Vector3d& axis) {
  Vector3d reference = Vector3d::UnitX() - axis.x() * axis;
  if (reference.norm() < kAlongXSine) reference = Vector3d::UnitY() - axis.y() * axis;
  return reference.normalized();
}

Vector3d ChooseReference(const Vector3d& axis, const std::optional<Vector3d>& reference) {
  if (!reference) return DefaultReference(axis);
  const Vector3d projected = *reference - reference->dot(axis) * axis;
  if (!projected.allFinite() || projected.norm() < 1e-6) {
    throw std::invalid_argument("Scene: the reference direction must not be along the axis");
  }
  return projected.normalized();
}

void CheckRadius(double radius) {
  if (!std::isfinite(radius) || radius <= 0) {
    throw std::invalid_argument("Scene: the pipe radius must be positive, got " +
                                std::to_string(radius));
  }
}

// Real roots of x^3 + p x + q: Cardano's formula in its cancellation-free form for one root,
// the trigonometric form for three; each polished by Newton steps.
int SolveDepressedCubic(double p, double q, double* roots) {
  int count = 0;
  const double discriminant = q * q / 4 + p * p * p / 27;
  if (discriminant > 0) {
    const double a = -std::copysign(std::cbrt(std::abs(q) / 2 + std::sqrt(discriminant)), q);
    roots[count++] = a - p / (3 * a);
  } else if (p < 0) {
    const double m = std::sqrt(-p / 3);
    const double angle = std::acos(std::clamp(3 * q / (2 * p * m), -1.0, 1.0)) / 3;
    for (int k = 0; k < 3; ++k) roots[count++] = 2 * m * std::cos(angle - kTwoPi * k / 3);
  } else {
    roots[count++] = 0;  // p = q = 0.
  }
  for (int i = 0; i < count; ++i) {
    for (int step = 0; step < 2; ++step) {
      const double x = roots[i];
      const double slope = 3 * x * x + p;
      if (slope != 0) roots[i] = x - ((x * x + p) * x + q) / slope;
    }
  }
  return count;
}

// f(s) = s^4 + c2 s^2 + c1 s + c0, the ray-torus quartic in a frame where the cubic term vanishes.
struct Quartic {
  double c2, c1, c0;
  double operator()(double s) const {
    const double s2 = s * s;
    return (s2 + c2) * s2 + c1 * s + c0;
  }
  double Derivative(double s) const { return (4 * s * s + 2 * c2) * s + c1; }
};

// The root of a quartic monotone on [a, b] with f(a), f(b) of opposite signs: Newton's method
// kept inside the shrinking bracket, bisection when Newton would leave it.
double BracketedRoot(const Quartic& f, double a, double b, double fa, double fb) {
  double x = a - fa * (b - a) / (fb - fa);
  if (!(x > a && x < b)) x = 0.5 * (a + b);
  const bool a_positive = fa > 0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double fx = f(x);
    if (fx == 0) return x;
    if ((fx > 0) == a_positive) {
      a = x;
    } else {
      b = x;
    }
    double next = x - fx / f.Derivative(x);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    if (std::abs(next - x) <= kRootTolerance || b - a <= kRootTolerance) return next;
    x = next;
  }
  return x;
}

// Real roots of the quartic in [lo, hi], ascending. Its critical points (roots of the cubic
// derivative) split the interval into monotone pieces with at most one root each; this is
// robust where closed-form quartic solutions lose accuracy (near-double roots at grazing rays).
int SolveQuarticInInterval(const Quartic& f, double lo, double hi, double* roots) {
  double critical[3];
  const int num_critical = SolveDepressedCubic(f.c2 / 2, f.c1 / 4, critical);
  std::sort(critical, critical + num_critical);
  double breaks[5];
  int num_breaks = 0;
  breaks[num_breaks++] = lo;
  for (int i = 0; i < num_critical; ++i) {
    if (critical[i] > lo && critical[i] < hi) breaks[num_breaks++] = critical[i];
  }
  breaks[num_breaks++] = hi;
  int count = 0;
  double fa = f(breaks[0]);
  for (int i = 0; i + 1 < num_breaks; ++i) {
    const double fb = f(breaks[i + 1]);
    if ((fa > 0) != (fb > 0)) roots[count++] = BracketedRoot(f, breaks[i], breaks[i + 1], fa, fb);
    fa = fb;
  }
  return count;
}

// Crossings of a straight section's boundary (at most two: it is convex) with t > 0, ascending.
int StraightEvents(const SectionGeometry& g, const Ray& ray, Event* events) {
  // Local frame: x along u, y along v, z along the axis.
  const Vector3d o = ray.origin - g.origin;
  const Vector3d& d = ray.direction;
  const double ox = o.dot(g.u), oy = o.dot(g.v), oz = o.dot(g.axis);
  const double dx = d.dot(g.u), dy = d.dot(g.v), dz = d.dot(g.axis);
  // Interval inside the infinite cylinder x^2 + y^2 < r^2. The root pair q / a, c / q has no
  // cancellation, so a nearly axial ray (tiny a) still gets an exact near root.
  double c_in = -kInf, c_out = kInf;
  const double a = dx * dx + dy * dy;
  const double b = ox * dx + oy * dy;
  const double c = ox * ox + oy * oy - g.radius_sq;
  if (a > 0) {
    const double discriminant = b * b - a * c;
    if (discriminant < 0) return 0;
    const double q = -(b + std::copysign(std::sqrt(discriminant), b));
    if (q == 0) return 0;  // Tangent at the origin.
    const double t1 = q / a, t2 = c / q;
    c_in = std::min(t1, t2);
    c_out = std::max(t1, t2);
  } else if (c >= 0) {
    return 0;
  }
  // Interval inside the axial slab.
  double s_in = -kInf, s_out = kInf;
  if (dz != 0) {
    s_in = (g.min_h - oz) / dz;
    s_out = (g.max_h - oz) / dz;
    if (s_in > s_out) std::swap(s_in, s_out);
  } else if (oz < g.min_h || oz > g.max_h) {
    return 0;
  }
  const double t_in = std::max(c_in, s_in), t_out = std::min(c_out, s_out);
  if (!(t_in < t_out)) return 0;
  int count = 0;
  if (t_in > 0) events[count++] = {t_in, c_in > s_in};
  if (t_out > 0) events[count++] = {t_out, c_out < s_out};
  return count;
}

// Entry and exit distances of the ray through a bend's bounding sphere (entry clamped to 0);
// false when it misses.
bool BoundingSphereInterval(const SectionGeometry& g, const Ray& ray, double* t_enter,
                            double* t_exit) {
  const Vector3d o = ray.origin - g.sphere_center;
  const double b = o.dot(ray.direction);
  const double discriminant = b * b - (o.squaredNorm() - g.sphere_radius_sq);
  if (!(discriminant >= 0)) return false;  // Also rejects NaN rays.
  const double root = std::sqrt(discriminant);
  *t_exit = -b + root;
  if (*t_exit <= 0) return false;
  *t_enter = std::max(0.0, -b - root);
  return true;
}

// Whether a point with bend-centre-relative offset `local` lies in the bend's angular range.
bool InBendRange(const SectionGeometry& g, const Vector3d& local) {
  const double du = local.dot(g.mid_u), dv = local.dot(g.mid_v);
  return du >= std::sqrt(du * du + dv * dv) * g.cos_half;
}

// Crossings of a bend's boundary (torus wall and the two end discs) with t in
// [t_enter, t_exit] and t > 0, ascending.
int BendEvents(const SectionGeometry& g, const Ray& ray, double t_enter, double t_exit,
               Event* events) {
  const Vector3d& d = ray.direction;
  const Vector3d o = ray.origin - g.origin;
  int count = 0;
  // Shift the parameter to the ray's closest approach to the bend centre, s = t - t0: the
  // quartic loses its cubic term and its coefficients stay of order (R + r)^4 however far
  // the camera is.
  const double t0 = -o.dot(d);
  const Vector3d q0 = o + t0 * d;
  const double q0_sq = q0.squaredNorm();
  const double outer = g.bend_radius + g.radius;
  const double span_sq = outer * outer - q0_sq;
  if (span_sq > 0) {
    const double span = std::sqrt(span_sq) + Scene::kInsideTolerance;
    const double lo = std::max(t_enter - t0, -span), hi = std::min(t_exit - t0, span);
    if (lo < hi) {
      // (|p|^2 + R^2 - r^2)^2 = 4 R^2 (|p|^2 - (p . axis)^2) with p = q0 + s d, |p|^2 = s^2 +
      // |q0|^2.
      const double r2 = g.bend_radius * g.bend_radius;
      const double qa = q0.dot(g.axis), da = d.dot(g.axis);
      const double k = q0_sq + r2 - g.radius_sq;
      const Quartic f{2 * k - 4 * r2 * (1 - da * da), 8 * r2 * qa * da,
                      k * k - 4 * r2 * (q0_sq - qa * qa)};
      double roots[4];
      const int num_roots = SolveQuarticInInterval(f, lo, hi, roots);
      for (int i = 0; i < num_roots; ++i) {
        const double t = t0 + roots[i];
        if (t > 0 && InBendRange(g, q0 + roots[i] * d)) events[count++] = {t, true};
      }
    }
  }
  for (int k = 0; k < 2; ++k) {
    const double denominator = g.cap_normal[k].dot(d);
    if (denominator == 0) continue;
    const double t = g.cap_normal[k].dot(g.cap_center[k] - ray.origin) / denominator;
    if (!(t > 0)) continue;
    if ((ray.origin + t * d - g.cap_center[k]).squaredNorm() <= g.radius_sq) {
      events[count++] = {t, false};
    }
  }
  // Insertion sort: at most six events.
  for (int i = 1; i < count; ++i) {
    for (int j = i; j > 0 && events[j].t < events[j - 1].t; --j) {
      std::swap(events[j], events[j - 1]);
    }
  }
  return count;
}

// Whether the point lies inside the section's interior grown by `margin` (negative: shrunk).
bool InsideSection(const SectionGeometry& g, const Vector3d& point, double margin) {
  const double r = g.radius + margin;
  if (!g.is_bend) {
    const Vector3d local = point - g.origin;
    const double z = local.dot(g.axis);
    if (z < g.min_h - margin || z > g.max_h + margin) return false;
    const double x = local.dot(g.u), y = local.dot(g.v);
    return x * x + y * y < r * r;
  }
  if ((point - g.sphere_center).squaredNorm() > g.sphere_radius_sq) return false;
  const Vector3d local = point - g.origin;
  const double z = local.dot(g.axis);
  const double du = local.dot(g.mid_u), dv = local.dot(g.mid_v);
  const double rho = std::sqrt(du * du + dv * dv);
  const double dr = rho - g.bend_radius;
  return dr * dr + z * z < r * r && du >= rho * g.cos_half;
}

double WrapAngle(double phi) {
  if (phi < 0) phi += kTwoPi;
  return phi >= kTwoPi ? 0 : phi;
}

}  // namespace

void PipeSection::FrameAt(double h, Vector3d* point, Vector3d* tangent, Vector3d* reference) const {
  if (type == SectionType::kStraight) {
    *point = start + h * start_direction;
    *tangent = start_direction;
    *reference = this->reference;
    return;
  }
  const Eigen::AngleAxisd rotation(h / bend_radius, bend_axis);
  *point = bend_center + rotation * (start - bend_center);
  *tangent = rotation * start_direction;
  *reference = rotation * this->reference;
}

Vector3d PipeSection::EndPoint() const { return end; }

Vector3d PipeSection::EndDirection() const {
  Vector3d point, tangent, reference;
  FrameAt(length, &point, &tangent, &reference);
  return tangent;
}

int Scene::AddStraight(const Vector3d& start, const Vector3d& end, double radius,
                       const std::optional<Vector3d>& reference) {
  CheckRadius(radius);
  const double length = (end - start).norm();
  if (!start.allFinite() || !end.allFinite() || !(length > 0)) {
    throw std::invalid_argument("Scene: a straight section needs distinct finite end points");
  }
  PipeSection section;
  section.type = SectionType::kStraight;
  section.radius = radius;
  section.start = start;
  section.start_direction = (end - start) / length;
  section.reference = ChooseReference(section.start_direction, reference);
  section.length = length;
  section.end = end;

  SectionGeometry g;
  g.is_bend = false;
  g.origin = start;
  g.axis = section.start_direction;
  g.u = section.reference;
  g.v = g.axis.cross(g.u);
  g.radius = radius;
  g.radius_sq = radius * radius;
  g.inv_radius = 1 / radius;
  g.min_h = -kJointOverlap;
  g.max_h = length + kJointOverlap;

  sections_.push_back(section);
  geometry_.push_back(g);
  entries_.push_back({false, static_cast<int>(sections_.size()) - 1});
  return static_cast<int>(sections_.size()) - 1;
}

int Scene::AddBend(const Vector3d& start, const Vector3d& start_direction,
                   const Vector3d& turn_direction, double bend_radius, double angle, double radius,
                   const std::optional<Vector3d>& reference) {
  CheckRadius(radius);
  if (!(bend_radius > radius) || !std::isfinite(bend_radius)) {
    throw std::invalid_argument("Scene: the bend radius must exceed the pipe radius");
  }
  if (!(angle > 0 && angle <= std::numbers::pi)) {
    throw std::invalid_argument("Scene: the bend angle must be in (0, pi]");
  }
  const Vector3d tangent = start_direction.normalized();
  if (!start.allFinite() || !tangent.allFinite() || !turn_direction.allFinite() ||
      std::abs(tangent.dot(turn_direction.normalized())) > 1e-6 || turn_direction.norm() == 0) {
    throw std::invalid_argument(
        "Scene: a bend needs a finite start and perpendicular start and turn directions");
  }
  // Remove the last rounding of the perpendicularity so the frame is exactly orthonormal.
  const Vector3d normal = (turn_direction - turn_direction.dot(tangent) * tangent).normalized();

  PipeSection section;
  section.type = SectionType::kBend;
  section.radius = radius;
  section.start = start;
  section.start_direction = tangent;
  section.reference = ChooseReference(tangent, reference);
  section.length = bend_radius * angle;
  section.bend_center = start + bend_radius * normal;
  section.bend_axis = tangent.cross(normal);
  section.bend_radius = bend_radius;
  section.bend_angle = angle;
  Vector3d end_direction, end_reference;
  section.FrameAt(section.length, &section.end, &end_direction, &end_reference);

  SectionGeometry g;
  g.is_bend = true;
  g.origin = section.bend_center;
  g.axis = section.bend_axis;
  g.u = -normal;
  g.v = tangent;  // = axis x u.
  g.radius = radius;
  g.radius_sq = radius * radius;
  g.bend_radius = bend_radius;
  // The same overlap as straights, measured along the centreline.
  const double overlap_angle = kJointOverlap / bend_radius;
  const double half = 0.5 * angle + overlap_angle;
  g.mid_angle = 0.5 * angle;
  g.mid_u = std::cos(g.mid_angle) * g.u + std::sin(g.mid_angle) * g.v;
  g.mid_v = g.axis.cross(g.mid_u);
  g.cos_half = std::cos(half);
  const double cap_angles[2] = {-overlap_angle, angle + overlap_angle};
  for (int k = 0; k < 2; ++k) {
    const double c = std::cos(cap_angles[k]), s = std::sin(cap_angles[k]);
    g.cap_center[k] = g.origin + bend_radius * (c * g.u + s * g.v);
    g.cap_normal[k] = -s * g.u + c * g.v;
  }
  g.ref_axis = section.reference.dot(g.axis);
  g.ref_u = section.reference.dot(g.u);
  // The smallest circle around the arc (centre on its bisector), grown by the pipe radius.
  // For an arc past pi the farthest point is the arc's middle rather than its ends.
  const double offset = bend_radius * std::cos(half);
  g.sphere_center = g.origin + offset * g.mid_u;
  const double arc_extent =
      std::max((g.cap_center[0] - g.sphere_center).norm(), std::abs(bend_radius - offset));
  const double sphere_radius = arc_extent + radius + 2 * kInsideTolerance;
  g.sphere_radius_sq = sphere_radius * sphere_radius;

  sections_.push_back(section);
  geometry_.push_back(g);
  entries_.push_back({false, static_cast<int>(sections_.size()) - 1});
  return static_cast<int>(sections_.size()) - 1;
}

void Scene::AddTee(const std::string& name, const Vector3d& center) {
  if (name.empty() || !center.allFinite()) {
    throw std::invalid_argument("Scene: a tee needs a name and a finite centre");
  }
  for (const Junction& junction : junctions_) {
    if (junction.name == name) {
      throw std::invalid_argument("Scene: duplicate junction name '" + name + "'");
    }
  }
  junctions_.push_back({name, center});
  entries_.push_back({true, static_cast<int>(junctions_.size()) - 1});
}

bool Scene::OnUnionBoundary(int section, const Vector3d& point, bool wall) const {
  // A wall point is hidden only deep inside another interior; an open disc is closed by any
  // section that reaches it. Both tolerances favour "wall", so seams never leak.
  const double margin = wall ? -kInsideTolerance : kInsideTolerance;
  for (int j = 0; j < static_cast<int>(geometry_.size()); ++j) {
    if (j != section && InsideSection(geometry_[j], point, margin)) return false;
  }
  return true;
}

bool Scene::FirstBoundaryCrossing(const Ray& ray, double* distance, int* section,
                                  bool* wall) const {
  // Sections in the order of a lower bound on their crossings: a straight's exact first
  // crossing, a bend's bounding sphere entry. Once a crossing on the union boundary is found,
  // sections that start behind it need no work (bends: no quartic).
  struct Candidate {
    double t_lo;
    double t_hi;  // Bends: bounding sphere exit.
    int section;
    int num_events;  // Straights: events already computed.
    Event events[2];
  };
  const int num_sections = static_cast<int>(geometry_.size());
  std::array<Candidate, kInlineSections> inline_candidates;
  std::vector<Candidate> heap_candidates;
  Candidate* candidates = inline_candidates.data();
  if (num_sections > kInlineSections) {
    heap_candidates.resize(num_sections);
    candidates = heap_candidates.data();
  }
  int num_candidates = 0;
  for (int i = 0; i < num_sections; ++i) {
    const SectionGeometry& g = geometry_[i];
    Candidate& candidate = candidates[num_candidates];
    candidate.section = i;
    if (g.is_bend) {
      if (!BoundingSphereInterval(g, ray, &candidate.t_lo, &candidate.t_hi)) continue;
      candidate.num_events = -1;
    } else {
      candidate.num_events = StraightEvents(g, ray, candidate.events);
      if (candidate.num_events == 0) continue;
      candidate.t_lo = candidate.events[0].t;
      candidate.t_hi = 0;
    }
    // Insertion by t_lo.
    int j = num_candidates++;
    const Candidate inserted = candidate;
    for (; j > 0 && candidates[j - 1].t_lo > inserted.t_lo; --j) candidates[j] = candidates[j - 1];
    candidates[j] = inserted;
  }

  double best = kInf;
  for (int c = 0; c < num_candidates; ++c) {
    const Candidate& candidate = candidates[c];
    if (candidate.t_lo >= best) break;
    Event bend_events[6];
    const Event* events = candidate.events;
    int num_events = candidate.num_events;
    if (num_events < 0) {
      num_events = BendEvents(geometry_[candidate.section], ray, candidate.t_lo,
                              std::min(candidate.t_hi, best), bend_events);
      events = bend_events;
    }
    for (int e = 0; e < num_events && events[e].t < best; ++e) {
      const Vector3d point = ray.origin + events[e].t * ray.direction;
      if (OnUnionBoundary(candidate.section, point, events[e].wall)) {
        best = events[e].t;
        *section = candidate.section;
        *wall = events[e].wall;
        break;
      }
    }
  }
  *distance = best;
  return best < kInf;
}

void Scene::MakeHit(const Ray& ray, double distance, int section, WallHit* out) const {
  const SectionGeometry& g = geometry_[section];
  WallHit& hit = *out;
  hit.distance = distance;
  hit.point = ray.origin + distance * ray.direction;
  hit.section = section;
  const Vector3d local = hit.point - g.origin;
  double phi = 0;
  if (!g.is_bend) {
    const double x = local.dot(g.u), y = local.dot(g.v);
    // The hit lies on the wall, x^2 + y^2 = r^2 to rounding: dividing by the radius normalises
    // without a square root and a division on the renderer's per-pixel path.
    hit.normal = -g.inv_radius * (x * g.u + y * g.v);
    hit.h_m = local.dot(g.axis);
    phi = std::atan2(y, x);
  } else {
    // Foot point on the arc, then phi in the start frame rotated back by the arc angle.
    const double z = local.dot(g.axis);
    const double du = local.dot(g.mid_u), dv = local.dot(g.mid_v);
    const double rho = std::sqrt(du * du + dv * dv);
    const double theta = g.mid_angle + std::atan2(dv, du);
    const Vector3d foot = g.origin + (g.bend_radius / rho) * (du * g.mid_u + dv * g.mid_v);
    hit.normal = (foot - hit.point).normalized();
    hit.h_m = g.bend_radius * theta;
    const double qu = rho - g.bend_radius;  // Radial offset from the foot, in-plane outward.
    phi = std::atan2(g.ref_axis * qu - g.ref_u * z, g.ref_axis * z + g.ref_u * qu);
  }
  hit.s_m = g.radius * WrapAngle(phi);
}

std::optional<WallHit> Scene::Intersect(const Ray& ray) const {
  WallHit hit;
  if (!Intersect(ray, &hit)) return std::nullopt;
  return hit;
}

bool Scene::Intersect(const Ray& ray, WallHit* hit) const {
  // One straight pipe (most presets): the union is the section itself, so its first crossing is
  // the answer, without the candidate list. The same arithmetic as the general path.
  if (geometry_.size() == 1 && !geometry_[0].is_bend) {
    Event events[2];
    if (StraightEvents(geometry_[0], ray, events) == 0 || !events[0].wall) return false;
    MakeHit(ray, events[0].t, 0, hit);
    return true;
  }
  double distance = 0;
  int section = -1;
  bool wall = false;
  if (!FirstBoundaryCrossing(ray, &distance, &section, &wall) || !wall) return false;
  MakeHit(ray, distance, section, hit);
  return true;
}

Scene::RayFan::RayFan(const Scene& scene, const Vector3d& origin) : scene_(scene), origin_(origin) {
  if (scene.geometry_.size() != 1 || scene.geometry_[0].is_bend) return;
  const SectionGeometry& g = scene.geometry_[0];
  const Vector3d o = origin - g.origin;
  ox_ = o.dot(g.u);
  oy_ = o.dot(g.v);
  oz_ = o.dot(g.axis);
  c_ = ox_ * ox_ + oy_ * oy_ - g.radius_sq;
  fast_ = c_ < 0 && oz_ > g.min_h && oz_ < g.max_h;
}

bool Scene::RayFan::Intersect(const Vector3d& direction, WallHit* hit) const {
  if (!fast_) return scene_.Intersect(Ray{origin_, direction}, hit);
  const SectionGeometry& g = scene_.geometry_[0];
  const double dx = direction.dot(g.u), dy = direction.dot(g.v), dz = direction.dot(g.axis);
  const double a = dx * dx + dy * dy;
  if (!(a > 0)) return false;  // along the axis: out through an open end
  // StraightEvents()' roots q / a and c / q; inside the cylinder (c < 0) they have opposite
  // signs and the ray leaves through the positive one. (q's sign decides, not b's: b may be -0.)
  const double b = ox_ * dx + oy_ * dy;
  const double q = -(b + std::copysign(std::sqrt(b * b - a * c_), b));
  const double t = q < 0 ? c_ / q : q / a;
  // Past the section's end the ray has left through the open disc first.
  const double z = oz_ + t * dz;
  if (!(z > g.min_h && z < g.max_h)) return false;
  const double x = ox_ + t * dx, y = oy_ + t * dy;
  hit->distance = t;
  hit->point = origin_ + t * direction;
  hit->normal = -g.inv_radius * (x * g.u + y * g.v);  // on the wall, as in MakeHit()
  hit->section = 0;
  hit->h_m = z;
  hit->s_m = g.radius * WrapAngle(std::atan2(y, x));
  return true;
}

bool Scene::Contains(const Vector3d& point) const {
  for (const SectionGeometry& g : geometry_) {
    if (InsideSection(g, point, 0)) return true;
  }
  return false;
}

}  // namespace pipescope
