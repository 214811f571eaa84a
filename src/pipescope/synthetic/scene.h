#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace pipescope {

// Pipe scene geometry of the simulator: straight sections (finite open cylinders), bends (torus
// pieces) and T-intersections, composed into networks in one world frame. Metres and radians;
// gravity "down" is +Y, a straight pipe's axis is the Z axis (GUIDE §3), networks lie in the
// X-Z plane.

// A ray in the world frame; `direction` must have unit length.
struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

enum class SectionType { kStraight, kBend };

// One piece of pipe: a finite open cylinder (straight) or a torus piece (bend).
struct PipeSection {
  SectionType type = SectionType::kStraight;
  double radius = 0;                                           // Inner radius of the pipe.
  Eigen::Vector3d start = Eigen::Vector3d::Zero();             // Centreline start point.
  Eigen::Vector3d start_direction = Eigen::Vector3d::UnitZ();  // Unit centreline tangent.
  // Unit, perpendicular to start_direction: the phi = 0 direction at the start.
  Eigen::Vector3d reference = Eigen::Vector3d::UnitX();
  // Centreline length: straight |end - start|, bend bend_radius * bend_angle.
  double length = 0;
  // Centreline end point: a straight's exactly as given (FrameAt(length) may differ by rounding).
  Eigen::Vector3d end = Eigen::Vector3d::Zero();

  // Bends only.
  Eigen::Vector3d bend_center = Eigen::Vector3d::Zero();  // Centre of the centreline arc.
  // Unit normal of the bend plane: the centreline turns by +angle (right-handed) about it.
  Eigen::Vector3d bend_axis = Eigen::Vector3d::Zero();
  double bend_radius = 0;  // Centreline radius of the arc.
  double bend_angle = 0;   // Radians, in (0, pi].

  Eigen::Vector3d EndPoint() const;
  Eigen::Vector3d EndDirection() const;

  // The centreline frame at arc length h from the start: point, unit tangent and the phi = 0
  // reference. The reference is parallel-transported; on a (planar) bend that is the rotation
  // about bend_axis, so it turns with the arc.
  void FrameAt(double h, Eigen::Vector3d* point, Eigen::Vector3d* tangent,
               Eigen::Vector3d* reference) const;
};

// Where a ray leaves the pipe interior.
struct WallHit {
  double distance = 0;                              // Along the ray.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // World frame.
  // Unit, pointing into the pipe interior (towards the centreline).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int section = -1;  // Index into Scene::sections().
  // Centreline arc length of the foot point from the section's start, in [0, length]; it may
  // stray up to Scene::kJointOverlap past the ends.
  double h_m = 0;
  // radius * phi, phi in [0, 2 pi) measured from the section's reference about the tangent
  // (right-handed: phi = 90 deg is tangent x reference).
  double s_m = 0;
};

namespace internal {

// Per-section data precomputed for Scene::Intersect; see scene.cc.
struct SectionGeometry {
  bool is_bend = false;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // Straight: start. Bend: bend centre.
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();    // Straight: unit axis. Bend: bend axis.
  Eigen::Vector3d u = Eigen::Vector3d::Zero();  // Straight: reference. Bend: unit (start - centre).
  Eigen::Vector3d v =
      Eigen::Vector3d::Zero();  // Straight: axis x reference. Bend: start direction.
  double radius = 0;
  double radius_sq = 0;
  double inv_radius = 0;
  double min_h = 0, max_h = 0;  // Straight: axial range including the joint overlap.
  // Bends.
  double bend_radius = 0;
  double mid_angle = 0;                             // Half the bend angle.
  Eigen::Vector3d mid_u = Eigen::Vector3d::Zero();  // Unit in-plane direction at mid_angle.
  Eigen::Vector3d mid_v = Eigen::Vector3d::Zero();  // axis x mid_u.
  double cos_half = 0;  // cos(half the angular range including the joint overlap).
  // Centreline points of the two end discs, and the tangents there (the discs' normals).
  Eigen::Vector3d cap_center[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Eigen::Vector3d cap_normal[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  double ref_axis = 0, ref_u = 0;  // Start reference = ref_axis * axis + ref_u * u.
  Eigen::Vector3d sphere_center = Eigen::Vector3d::Zero();  // Bounding sphere of the torus piece.
  double sphere_radius_sq = 0;
};

}  // namespace internal

// A network of pipe sections. The wall is the boundary of the union of the section interiors,
// so a camera in a T sees into the branch; the ends of the network are open.
class Scene {
 public:
  // Each section's interior extends this far past its ends (metres of centreline) so that
  // joints between consecutive sections, and a branch meeting its through run, are watertight:
  // rounding can never open a crack between two sections. It must exceed the rounding of axial
  // coordinates in a network of tens of metres (~1e-14 m) and stay invisible (far below a
  // pixel's footprint, ~1e-4 m). Where consecutive sections are not collinear the extended
  // walls deviate from each other by ~kJointOverlap^2 / bend_radius ~ 1e-12 m, far below
  // kInsideTolerance, so the union test sees them as one surface.
  static constexpr double kJointOverlap = 1e-6;
  // A wall point of one section hides behind another section only when it lies deeper than
  // this inside that section's interior; a disc crossing (open end) counts as covered by
  // another section within this margin. Keeps seams crack-free.
  static constexpr double kInsideTolerance = 1e-9;

  // Straight section from start to end (their centreline points). reference: the phi = 0
  // direction, projected perpendicular to the axis; default world +X so projected (or +Y when
  // the axis is within 1e-3 rad of X), so for a pipe along +Z phi = atan2(Y, X) (000 eq. 1).
  // Returns the section index. Throws std::invalid_argument for degenerate geometry.
  int AddStraight(const Eigen::Vector3d& start, const Eigen::Vector3d& end, double radius,
                  const std::optional<Eigen::Vector3d>& reference = std::nullopt);

  // Bend continuing from start along start_direction, turning towards turn_direction
  // (perpendicular to start_direction) with centreline radius bend_radius (> radius) through
  // angle (radians, in (0, pi]). reference as for AddStraight, perpendicular to
  // start_direction; pass the previous section's end reference (FrameAt(length)) for a
  // continuous phi across the joint. Returns the section index; throws std::invalid_argument.
  int AddBend(const Eigen::Vector3d& start, const Eigen::Vector3d& start_direction,
              const Eigen::Vector3d& turn_direction, double bend_radius, double angle,
              double radius, const std::optional<Eigen::Vector3d>& reference = std::nullopt);

  // A T-intersection: recorded as a named junction at `center` (where the two axes meet,
  // 001 Fig. 4b) and as an entry of type tee in the route order. Its geometry is the straight
  // sections the caller adds: the through run passes the centre, the branch starts at it.
  // Names must be unique (scene.yaml readers reject duplicates); throws std::invalid_argument.
  void AddTee(const std::string& name, const Eigen::Vector3d& center);

  const std::vector<PipeSection>& sections() const { return sections_; }

  struct Junction {
    std::string name;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
  };
  const std::vector<Junction>& junctions() const { return junctions_; }

  // Route-ordered entries for scene.yaml: a section index, or a junction index for a tee.
  struct Entry {
    bool is_tee = false;
    int index = 0;
  };
  const std::vector<Entry>& entries() const { return entries_; }

  // The first point where a ray starting inside the union of the interiors leaves it; nullopt
  // when it leaves through an open end of the network (the dark far end of a pipe) or never
  // leaves. Thread-safe, no heap allocation for scenes of up to 64 sections.
  std::optional<WallHit> Intersect(const Ray& ray) const;
  // The same, writing the hit into *hit (left unspecified when there is none): the renderer's
  // per-pixel call, without the optional's copy.
  bool Intersect(const Ray& ray, WallHit* hit) const;

  // True when the point lies strictly inside the union of the interiors.
  bool Contains(const Eigen::Vector3d& point) const;

  // Rays from one origin through many directions, as a camera casts them. In a scene of one
  // straight section with the origin inside, what depends only on the origin is computed once
  // and a ray costs one square root and one division; otherwise each ray goes to Intersect().
  // The hits agree with Intersect()'s to rounding. Holds a reference to the scene.
  class RayFan {
   public:
    RayFan(const Scene& scene, const Eigen::Vector3d& origin);
    // As Scene::Intersect(ray, hit) for the ray from the origin along the unit `direction`.
    bool Intersect(const Eigen::Vector3d& direction, WallHit* hit) const;

   private:
    const Scene& scene_;
    Eigen::Vector3d origin_;
    bool fast_ = false;                // one straight section, origin strictly inside
    double ox_ = 0, oy_ = 0, oz_ = 0;  // origin in the section's frame
    double c_ = 0;                     // ox^2 + oy^2 - r^2 < 0
  };

 private:
  // The first boundary crossing of the union along the ray: its distance, section and whether
  // it is a wall (else an open disc). False when there is none.
  bool FirstBoundaryCrossing(const Ray& ray, double* distance, int* section, bool* wall) const;
  // Whether a crossing of `section`'s boundary at `point` is a boundary of the union.
  bool OnUnionBoundary(int section, const Eigen::Vector3d& point, bool wall) const;
  void MakeHit(const Ray& ray, double distance, int section, WallHit* hit) const;

  std::vector<PipeSection> sections_;
  std::vector<internal::SectionGeometry> geometry_;
  std::vector<Junction> junctions_;
  std::vector<Entry> entries_;
};

}  // namespace pipescope
