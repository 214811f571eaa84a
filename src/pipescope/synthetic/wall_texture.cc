#include "pipescope/synthetic/wall_texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define PIPESCOPE_WALL_TEXTURE_AVX2 1
#endif

// The scalar and AVX2 paths must round alike, so no fused multiply-adds even in builds for CPUs
// that have them (-march=native).
#if defined(__clang__)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// ---------------------------------------------------------------------------------------------
// Small helpers. Nothing per call allocates or calls the library; no std::floor, which is a
// library call in the baseline x86-64 build (no SSE4.1).

constexpr double kTwoPi = 6.283185307179586;

inline std::int64_t FloorToInt(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return i - (x < static_cast<double>(i));
}

inline double Truncate(double x) { return static_cast<double>(static_cast<std::int64_t>(x)); }

inline float Clamp01(float x) { return std::min(1.0f, std::max(0.0f, x)); }

inline float SmoothStep(float edge0, float edge1, float x) {
  const float t = Clamp01((x - edge0) / (edge1 - edge0));
  return t * t * (3 - 2 * t);
}

inline float Lerp(float a, float b, float t) { return a + (b - a) * t; }

// lowbias32 (C. Wellons): a full-avalanche 32-bit integer hash, two multiplies.
inline std::uint32_t Hash(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// Lattice point (i, j) is hashed as Hash(i * kPrimeI + j + seed): neighbouring corners cost an
// addition each. Like any linear key mod 2^32 it repeats along one lattice vector, here
// (50549, -11547) cells: metres even at the finest octave, and only that octave repeats.
constexpr std::uint32_t kPrimeI = 0x9E3779B1U;

// Uniforms in [0, 1): 24 bits of a hash, or either 16-bit half.
inline float Uniform(std::uint32_t hash) {
  return static_cast<float>(hash >> 8) * (1.0f / 16777216.0f);
}
inline float LowUniform(std::uint32_t hash) {
  return static_cast<float>(hash & 0xffffU) * (1.0f / 65536.0f);
}
inline float HighUniform(std::uint32_t hash) {
  return static_cast<float>(hash >> 16) * (1.0f / 65536.0f);
}

// Gradient noise picks one of 8 gradients (22.5 + 45 k degrees, so none is axis-aligned) with
// the low 3 bits of the corner's hash. Their length, 1.5, scales the noise to a standard
// deviation of about 1/3, so it stays mostly within [-1, 1] (measured over 10^6 samples).
alignas(32) constexpr std::array<float, 8> kGradientX = {1.38582f,  0.57403f,  -0.57403f, -1.38582f,
                                                         -1.38582f, -0.57403f, 0.57403f,  1.38582f};
alignas(32) constexpr std::array<float, 8> kGradientY = {
    0.57403f, 1.38582f, 1.38582f, 0.57403f, -0.57403f, -1.38582f, -1.38582f, -0.57403f};

inline float Gradient(std::uint32_t hash, float x, float y) {
  return kGradientX[hash & 7U] * x + kGradientY[hash & 7U] * y;
}

inline float Fade(float t) { return t * t * t * (t * (t * 6 - 15) + 10); }

// The procedural mip-map rule: a feature of size L is kept whole down to 3 footprints and gone at
// 1.5 footprints (Nyquist is 2 footprints per period).
inline float FootprintWeight(double size_m, double inv_footprint) {
  const float t = Clamp01((static_cast<float>(size_m * inv_footprint) - 1.5f) * (1 / 1.5f));
  return t * t * (3 - 2 * t);
}

// ---------------------------------------------------------------------------------------------
// Lattice lanes. Everything hashed on a lattice is a lane: a lattice of `rows` rows around the
// circumference, an integer so it wraps exactly (cells stretch by a few percent at most, except
// the coarsest), helical when the wrapped row is shifted by `shear` columns. Per call all lanes
// are evaluated together, with AVX2 where the CPU has it (several times cheaper than scalar
// code):
//  - 8 noise lanes (the stain octaves, and the fibre winding for fiberglass): gradient noise
//    with a quintic fade (C2, so no cell seams), faded by the footprint;
//  - 4 cell lanes (2 pit grids, 2 scratch grids; square cells, no shear): the cell's hash and
//    the position in it.
// The scalar path does the same IEEE operations in the same order (no FMA), so both paths give
// bit-identical values.

constexpr int kNumNoiseLanes = 8;
constexpr int kNumCellLanes = 4;
constexpr int kPitLane = 0;      // cell lanes of the two pit grids
constexpr int kScratchLane = 2;  // cell lanes of the two scratch grids
constexpr int kWeaveLane = 6;    // noise lanes of the two fibre families, when there are any

// Stain octaves run from 0.3 m down to 0.1 mm; those of 1 mm and finer also roughen rust, weld
// beads and paint.
constexpr double kCoarsestCellM = 0.3;
constexpr double kFinestCellM = 1e-4;
constexpr double kFineCellM = 1.001e-3;

struct LaneTable {
  // Noise lane k: x = h * inv_along + u * shear, y = u * rows, with
  // rows = max(1, round(C * inv_around)) and shear = round(C * shear_per_m).
  alignas(32) std::array<double, kNumNoiseLanes> inv_along;
  alignas(32) std::array<double, kNumNoiseLanes> inv_around;
  alignas(32) std::array<double, kNumNoiseLanes> shear_per_m;
  alignas(32) std::array<double, kNumNoiseLanes> size_m;       // for FootprintWeight()
  alignas(32) std::array<std::uint32_t, kNumNoiseLanes> salt;  // seed = section seed + salt
  alignas(32) std::array<float, kNumNoiseLanes> stain_amplitude;
  alignas(32) std::array<float, kNumNoiseLanes> fine_amplitude;
  // Cell lane k: square cells of 1 / inv_cell metres.
  alignas(32) std::array<double, kNumCellLanes> inv_cell;
  alignas(16) std::array<std::uint32_t, kNumCellLanes> cell_salt;
};

// Stencil letter height of the markings: 6% of the circumference, 15 to 50 mm.
double LetterHeight(double circumference_m) {
  return std::min(0.05, std::max(0.015, 0.06 * circumference_m));
}

// The lattices' sizes around one circumference, as doubles for the lattice arithmetic: rows, the
// last row, shears; and as integers for the wrap: rows and shear * kPrimeI.
struct LaneGeometry {
  alignas(32) std::array<double, kNumNoiseLanes> rows;
  alignas(32) std::array<double, kNumNoiseLanes> last_row;
  alignas(32) std::array<double, kNumNoiseLanes> shear;
  alignas(32) std::array<double, kNumCellLanes> cell_rows;
  alignas(32) std::array<double, kNumCellLanes> cell_last_row;
  alignas(32) std::array<std::int32_t, kNumNoiseLanes> rows_int;
  alignas(32) std::array<std::uint32_t, kNumNoiseLanes> wrap_offset;
  double inv_circumference_m;
  double letter_m;  // of the markings
  double inv_letter_m;
};

LaneGeometry MakeLaneGeometry(const LaneTable& table, double circumference_m) {
  LaneGeometry geometry;
  for (int k = 0; k < kNumNoiseLanes; ++k) {
    geometry.rows[k] = std::max(Truncate(circumference_m * table.inv_around[k] + 0.5), 1.0);
    geometry.last_row[k] = geometry.rows[k] - 1;
    geometry.shear[k] = Truncate(circumference_m * table.shear_per_m[k] + 0.5);
    geometry.rows_int[k] = static_cast<std::int32_t>(geometry.rows[k]);
    geometry.wrap_offset[k] =
        static_cast<std::uint32_t>(static_cast<std::int32_t>(geometry.shear[k])) * kPrimeI;
  }
  for (int k = 0; k < kNumCellLanes; ++k) {
    geometry.cell_rows[k] = std::max(Truncate(circumference_m * table.inv_cell[k] + 0.5), 1.0);
    geometry.cell_last_row[k] = geometry.cell_rows[k] - 1;
  }
  geometry.inv_circumference_m = 1 / circumference_m;
  geometry.letter_m = LetterHeight(circumference_m);
  geometry.inv_letter_m = 1 / geometry.letter_m;
  return geometry;
}

// The geometry depends only on the circumference, and a renderer asks for one or two per frame,
// so each thread keeps the last one it made: that takes the conversions off the per-call chain.
const LaneGeometry& GeometryFor(const LaneTable& table, double circumference_m) {
  struct Cache {
    const LaneTable* table = nullptr;
    double circumference_m = 0;
    LaneGeometry geometry;
  };
  thread_local Cache cache;
  if (cache.table != &table || cache.circumference_m != circumference_m) {
    cache.geometry = MakeLaneGeometry(table, circumference_m);
    cache.table = &table;
    cache.circumference_m = circumference_m;
  }
  return cache.geometry;
}

struct LaneQuery {
  double h_m;
  double u;  // s / circumference in [0, 1)
  double inv_footprint;
  std::uint32_t section_seed;
  const LaneGeometry* geometry;
};

struct LaneResult {
  alignas(32) std::array<float, kNumNoiseLanes> noise;  // faded by the footprint
  alignas(16) std::array<std::uint32_t, kNumCellLanes> cell_hash;
  alignas(16) std::array<float, kNumCellLanes> cell_x;  // position in the cell, [0, 1)
  alignas(16) std::array<float, kNumCellLanes> cell_y;
  float stain;  // sum of stain_amplitude * noise
  float fine;   // sum of fine_amplitude * noise
};

// Sums 8 terms in the order the AVX2 path does: k and k + 4, then k and k + 2, then the two.
inline float ReduceLanes(const std::array<float, kNumNoiseLanes>& terms) {
  float r[4];
  for (int k = 0; k < 4; ++k) r[k] = terms[k] + terms[k + 4];
  return (r[0] + r[2]) + (r[1] + r[3]);
}

// Lattice coordinates of one lane: integer parts as int32 (floor), fractions as float.
struct LatticePoint {
  std::int32_t ix;
  std::int32_t iy;
  float fx;
  float fy;
};

inline LatticePoint Locate(double x, double y, double last_row) {
  const auto floor_x = static_cast<double>(FloorToInt(x));
  const double floor_y = std::min(static_cast<double>(FloorToInt(y)), last_row);
  return {static_cast<std::int32_t>(floor_x), static_cast<std::int32_t>(floor_y),
          static_cast<float>(x - floor_x), std::min(static_cast<float>(y - floor_y), 1.0f)};
}

void EvaluateLanesScalar(const LaneTable& table, const LaneQuery& query, LaneResult* result) {
  const LaneGeometry& geometry = *query.geometry;
  std::array<float, kNumNoiseLanes> stain_terms;
  std::array<float, kNumNoiseLanes> fine_terms;
  for (int k = 0; k < kNumNoiseLanes; ++k) {
    const LatticePoint p = Locate(query.h_m * table.inv_along[k] + query.u * geometry.shear[k],
                                  query.u * geometry.rows[k], geometry.last_row[k]);
    const std::uint32_t seed = query.section_seed + table.salt[k];
    // Lattice point (i, j) hashes as Hash(i * kPrimeI + j + seed); the row after the last is
    // row 0, shifted by `shear` columns on a helical lattice.
    const std::uint32_t a = static_cast<std::uint32_t>(p.ix) * kPrimeI;
    const std::uint32_t b = a + kPrimeI;
    const std::uint32_t c = static_cast<std::uint32_t>(p.iy) + seed;
    const std::uint32_t d =
        p.iy + 1 == geometry.rows_int[k] ? seed - geometry.wrap_offset[k] : c + 1;
    const float g00 = Gradient(Hash(a + c), p.fx, p.fy);
    const float g10 = Gradient(Hash(b + c), p.fx - 1, p.fy);
    const float g01 = Gradient(Hash(a + d), p.fx, p.fy - 1);
    const float g11 = Gradient(Hash(b + d), p.fx - 1, p.fy - 1);
    const float ux = Fade(p.fx);
    const float value = Lerp(Lerp(g00, g10, ux), Lerp(g01, g11, ux), Fade(p.fy));
    const float noise = FootprintWeight(table.size_m[k], query.inv_footprint) * value;
    result->noise[k] = noise;
    stain_terms[k] = table.stain_amplitude[k] * noise;
    fine_terms[k] = table.fine_amplitude[k] * noise;
  }
  result->stain = ReduceLanes(stain_terms);
  result->fine = ReduceLanes(fine_terms);
  for (int k = 0; k < kNumCellLanes; ++k) {
    const LatticePoint p = Locate(query.h_m * table.inv_cell[k], query.u * geometry.cell_rows[k],
                                  geometry.cell_last_row[k]);
    result->cell_hash[k] =
        Hash(static_cast<std::uint32_t>(p.ix) * kPrimeI + static_cast<std::uint32_t>(p.iy) +
             query.section_seed + table.cell_salt[k]);
    result->cell_x[k] = p.fx;
    result->cell_y[k] = p.fy;
  }
}

#ifdef PIPESCOPE_WALL_TEXTURE_AVX2

#define PIPESCOPE_AVX2 __attribute__((target("avx2"))) inline

PIPESCOPE_AVX2 __m256i HashAvx2(__m256i x) {
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(0x7feb352d));
  x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
  x = _mm256_mullo_epi32(x, _mm256_set1_epi32(static_cast<int>(0x846ca68bU)));
  return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}

PIPESCOPE_AVX2 __m128i HashSse(__m128i x) {
  x = _mm_xor_si128(x, _mm_srli_epi32(x, 16));
  x = _mm_mullo_epi32(x, _mm_set1_epi32(0x7feb352d));
  x = _mm_xor_si128(x, _mm_srli_epi32(x, 15));
  x = _mm_mullo_epi32(x, _mm_set1_epi32(static_cast<int>(0x846ca68bU)));
  return _mm_xor_si128(x, _mm_srli_epi32(x, 16));
}

// The gradient table lookup is a lane permute, which runs on a port the arithmetic leaves idle.
PIPESCOPE_AVX2 __m256 GradientAvx2(__m256i hash, __m256 x, __m256 y) {
  const __m256 gx = _mm256_permutevar8x32_ps(_mm256_load_ps(kGradientX.data()), hash);
  const __m256 gy = _mm256_permutevar8x32_ps(_mm256_load_ps(kGradientY.data()), hash);
  return _mm256_add_ps(_mm256_mul_ps(gx, x), _mm256_mul_ps(gy, y));
}

PIPESCOPE_AVX2 __m256 FadeAvx2(__m256 t) {
  const __m256 cube = _mm256_mul_ps(_mm256_mul_ps(t, t), t);
  const __m256 inner = _mm256_sub_ps(_mm256_mul_ps(t, _mm256_set1_ps(6)), _mm256_set1_ps(15));
  return _mm256_mul_ps(cube, _mm256_add_ps(_mm256_mul_ps(t, inner), _mm256_set1_ps(10)));
}

PIPESCOPE_AVX2 __m256 LerpAvx2(__m256 a, __m256 b, __m256 t) {
  return _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t));
}

// Locate() on 4 lanes: floor (clamped to the last row in y) and fractions.
PIPESCOPE_AVX2 void LocateAvx2(__m256d x, __m256d y, __m256d last_row, __m128i* ix, __m128i* iy,
                               __m128* fx, __m128* fy) {
  constexpr int kFloor = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
  const __m256d floor_x = _mm256_round_pd(x, kFloor);
  const __m256d floor_y = _mm256_min_pd(_mm256_round_pd(y, kFloor), last_row);
  *ix = _mm256_cvttpd_epi32(floor_x);
  *iy = _mm256_cvttpd_epi32(floor_y);
  *fx = _mm256_cvtpd_ps(_mm256_sub_pd(x, floor_x));
  *fy = _mm_min_ps(_mm256_cvtpd_ps(_mm256_sub_pd(y, floor_y)), _mm_set1_ps(1));
}

// EvaluateLanesScalar(), operation for operation.
__attribute__((target("avx2"))) void EvaluateLanesAvx2(const LaneTable& table,
                                                       const LaneQuery& query, LaneResult* result) {
  const LaneGeometry& geometry = *query.geometry;
  const __m256d h = _mm256_set1_pd(query.h_m);
  const __m256d u = _mm256_set1_pd(query.u);
  const __m128i section_seed = _mm_set1_epi32(static_cast<int>(query.section_seed));
  const __m256i prime_i = _mm256_set1_epi32(static_cast<int>(kPrimeI));

  // Cell lanes first: short, and independent of the noise lanes.
  {
    __m128i ix, iy;
    __m128 fx, fy;
    LocateAvx2(_mm256_mul_pd(h, _mm256_load_pd(table.inv_cell.data())),
               _mm256_mul_pd(u, _mm256_load_pd(geometry.cell_rows.data())),
               _mm256_load_pd(geometry.cell_last_row.data()), &ix, &iy, &fx, &fy);
    const __m128i key = _mm_add_epi32(
        _mm_add_epi32(_mm_add_epi32(_mm_mullo_epi32(ix, _mm256_castsi256_si128(prime_i)), iy),
                      section_seed),
        _mm_load_si128(reinterpret_cast<const __m128i*>(table.cell_salt.data())));
    _mm_store_si128(reinterpret_cast<__m128i*>(result->cell_hash.data()), HashSse(key));
    _mm_store_ps(result->cell_x.data(), fx);
    _mm_store_ps(result->cell_y.data(), fy);
  }

  // Noise lanes, doubles 4 to a register.
  __m128i ix[2], iy[2];
  __m128 fx[2], fy[2], weight_arg[2];
  for (int q = 0; q < 2; ++q) {
    const int k = 4 * q;
    const __m256d x = _mm256_add_pd(_mm256_mul_pd(h, _mm256_load_pd(&table.inv_along[k])),
                                    _mm256_mul_pd(u, _mm256_load_pd(&geometry.shear[k])));
    LocateAvx2(x, _mm256_mul_pd(u, _mm256_load_pd(&geometry.rows[k])),
               _mm256_load_pd(&geometry.last_row[k]), &ix[q], &iy[q], &fx[q], &fy[q]);
    weight_arg[q] = _mm256_cvtpd_ps(
        _mm256_mul_pd(_mm256_load_pd(&table.size_m[k]), _mm256_set1_pd(query.inv_footprint)));
  }
  const __m256 one_f = _mm256_set1_ps(1);
  const __m256 fx8 = _mm256_set_m128(fx[1], fx[0]);
  const __m256 fy8 = _mm256_set_m128(fy[1], fy[0]);
  const __m256i iy8 = _mm256_set_m128i(iy[1], iy[0]);
  const __m256i seed =
      _mm256_add_epi32(_mm256_set_m128i(section_seed, section_seed),
                       _mm256_load_si256(reinterpret_cast<const __m256i*>(table.salt.data())));
  const __m256i a = _mm256_mullo_epi32(_mm256_set_m128i(ix[1], ix[0]), prime_i);
  const __m256i b = _mm256_add_epi32(a, prime_i);
  const __m256i c = _mm256_add_epi32(iy8, seed);
  const __m256i wraps = _mm256_cmpeq_epi32(
      _mm256_add_epi32(iy8, _mm256_set1_epi32(1)),
      _mm256_load_si256(reinterpret_cast<const __m256i*>(geometry.rows_int.data())));
  const __m256i d = _mm256_blendv_epi8(
      _mm256_add_epi32(c, _mm256_set1_epi32(1)),
      _mm256_sub_epi32(
          seed, _mm256_load_si256(reinterpret_cast<const __m256i*>(geometry.wrap_offset.data()))),
      wraps);
  const __m256 fx1 = _mm256_sub_ps(fx8, one_f);
  const __m256 fy1 = _mm256_sub_ps(fy8, one_f);
  const __m256 g00 = GradientAvx2(HashAvx2(_mm256_add_epi32(a, c)), fx8, fy8);
  const __m256 g10 = GradientAvx2(HashAvx2(_mm256_add_epi32(b, c)), fx1, fy8);
  const __m256 g01 = GradientAvx2(HashAvx2(_mm256_add_epi32(a, d)), fx8, fy1);
  const __m256 g11 = GradientAvx2(HashAvx2(_mm256_add_epi32(b, d)), fx1, fy1);
  const __m256 ux = FadeAvx2(fx8);
  const __m256 value = LerpAvx2(LerpAvx2(g00, g10, ux), LerpAvx2(g01, g11, ux), FadeAvx2(fy8));
  // FootprintWeight().
  const __m256 t = _mm256_min_ps(
      _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_set_m128(weight_arg[1], weight_arg[0]),
                                                _mm256_set1_ps(1.5f)),
                                  _mm256_set1_ps(1 / 1.5f)),
                    _mm256_setzero_ps()),
      one_f);
  const __m256 weight = _mm256_mul_ps(
      _mm256_mul_ps(t, t), _mm256_sub_ps(_mm256_set1_ps(3), _mm256_mul_ps(_mm256_set1_ps(2), t)));
  const __m256 noise = _mm256_mul_ps(weight, value);
  _mm256_store_ps(result->noise.data(), noise);
  // ReduceLanes() of the stain and fine terms.
  const auto reduce = [](__m256 terms) __attribute__((target("avx2"))) {
    const __m128 r = _mm_add_ps(_mm256_castps256_ps128(terms), _mm256_extractf128_ps(terms, 1));
    const __m128 s = _mm_add_ps(r, _mm_movehl_ps(r, r));
    return _mm_cvtss_f32(_mm_add_ss(s, _mm_shuffle_ps(s, s, 1)));
  };
  result->stain = reduce(_mm256_mul_ps(_mm256_load_ps(table.stain_amplitude.data()), noise));
  result->fine = reduce(_mm256_mul_ps(_mm256_load_ps(table.fine_amplitude.data()), noise));
}

#undef PIPESCOPE_AVX2

bool CpuHasAvx2() { return __builtin_cpu_supports("avx2"); }
#else
bool CpuHasAvx2() { return false; }
#endif

// ---------------------------------------------------------------------------------------------
// Material looks. Albedos are in [0, 1]; amplitudes multiply noise of standard deviation ~1/3.

// Pits and scratches live in square cells of `cell_m`, at most one per cell, kept clear of the
// cell's border so no feature is ever cut by a cell seam. Around the circumference the cells
// stretch (by a few percent) to divide it exactly; features are laid out in nominal cell units,
// so they stretch with them.

// Pits: present with `probability` (times a smooth local density), a dark disc of radius in
// [radius_min_m, radius_max_m] skewed to small ones. cell_m >= 4 radius_max_m keeps the filtered
// disc inside its cell.
struct PitGrid {
  double cell_m = 0;
  float probability = 0;
  float radius_min_m = 0;
  float radius_max_m = 0;
  float darkness = 0;  // albedo factor 1 - darkness at the pit's centre
};

// Scratches: straight segments along the axis with slopes |ds/dh| up to max_slope; with
// any_direction, half of them run around the pipe instead (slopes then measured from the
// circumference).
struct ScratchGrid {
  double cell_m = 0;
  float probability = 0;
  float width_min_m = 0;
  float width_max_m = 0;
  float max_slope = 0;         // |ds/dh| of the axial ones, <= 1
  bool any_direction = false;  // half of them run closer to the circumference
  float bright_fraction = 0;   // share of bright (bare metal) scratches, the rest are dark
  float amplitude = 0;         // albedo change along a sharp scratch
};
constexpr float kScratchMarginM = 1.5e-3f;

enum class JointStyle { kWeld, kFlange, kGap };

struct MaterialLook {
  float base_albedo;
  int num_octaves;  // 8, or 6 to leave two noise lanes to the fibre winding
  std::array<float, 8> octave_amplitude;
  // Rust blotches: a soft threshold on a low-frequency field (std ~0.45); no rust when
  // rust_threshold is large.
  float rust_threshold;
  float rust_albedo;
  float rust_roughness;  // gain on the fine octaves inside rust
  float weave_amplitude;
  float aggregate_amplitude;
  std::array<PitGrid, 2> pits;
  std::array<ScratchGrid, 2> scratches;
  JointStyle joint_style;
  float joint_half_width_m;       // weld bead, flange gap or segment gap
  float joint_band_half_width_m;  // heat-affected zone, adhesive band or stained edge
  float joint_albedo;
  float joint_band_delta;  // albedo change in the band
  float text_albedo;
  float ring_albedo;
  float specular_base;
  float specular_bare;  // scratches and weld beads
  float specular_rust;
  float specular_paint;
};

// Carbon steel (000 Fig. 1): mid grey mill scale, rust blotches, many scratches, girth welds
// with a rippled bead and a darker heat-tinted zone, white stencil paint.
constexpr MaterialLook kSteelLook = {
    .base_albedo = 0.42f,
    .num_octaves = 8,
    .octave_amplitude = {0.16f, 0.13f, 0.11f, 0.09f, 0.08f, 0.075f, 0.07f, 0.065f},
    .rust_threshold = 0.38f,
    .rust_albedo = 0.26f,
    .rust_roughness = 2.0f,
    .weave_amplitude = 0,
    .aggregate_amplitude = 0,
    .pits = {PitGrid{1.5e-3, 0.05f, 1e-4f, 3.5e-4f, 0.55f},
             PitGrid{6e-3, 0.12f, 3.5e-4f, 1e-3f, 0.6f}},
    .scratches = {ScratchGrid{0.025, 0.35f, 4e-5f, 2.5e-4f, 0.35f, false, 0.7f, 0.22f},
                  ScratchGrid{0.08, 0.3f, 6e-5f, 3e-4f, 1.0f, true, 0.6f, 0.18f}},
    .joint_style = JointStyle::kWeld,
    .joint_half_width_m = 0.006f,
    .joint_band_half_width_m = 0.02f,
    .joint_albedo = 0.5f,
    .joint_band_delta = -0.1f,
    .text_albedo = 0.88f,
    .ring_albedo = 0.75f,
    .specular_base = 0.35f,
    .specular_bare = 0.85f,
    .specular_rust = 0.05f,
    .specular_paint = 0.2f,
};

// Filament-wound fiberglass (001): light, glossy resin, low-contrast stains, fibre bundles
// wound at +-55 degrees to the axis, flange joints, prominent dark lettering.
constexpr MaterialLook kFiberglassLook = {
    .base_albedo = 0.64f,
    .num_octaves = 6,
    .octave_amplitude = {0.06f, 0.045f, 0.035f, 0.025f, 0.022f, 0.02f, 0, 0},
    .rust_threshold = 100.0f,
    .rust_albedo = 0,
    .rust_roughness = 0,
    .weave_amplitude = 0.045f,
    .aggregate_amplitude = 0,
    .pits = {PitGrid{1.5e-3, 0.01f, 1e-4f, 3e-4f, 0.3f}, PitGrid{}},
    .scratches = {ScratchGrid{0.04, 0.12f, 4e-5f, 1.5e-4f, 1.0f, true, 0.3f, 0.1f}, ScratchGrid{}},
    .joint_style = JointStyle::kFlange,
    .joint_half_width_m = 0.0015f,
    .joint_band_half_width_m = 0.03f,
    .joint_albedo = 0.12f,
    .joint_band_delta = -0.07f,
    .text_albedo = 0.08f,
    .ring_albedo = 0.3f,
    .specular_base = 0.5f,
    .specular_bare = 0.5f,
    .specular_rust = 0.5f,
    .specular_paint = 0.3f,
};

// Precast concrete culvert (003): matte, aggregate speckle, air-void pits, dark gaps at the
// segment joints, white spray paint.
constexpr MaterialLook kConcreteLook = {
    .base_albedo = 0.5f,
    .num_octaves = 8,
    .octave_amplitude = {0.1f, 0.085f, 0.075f, 0.07f, 0.06f, 0.07f, 0.07f, 0.065f},
    .rust_threshold = 100.0f,
    .rust_albedo = 0,
    .rust_roughness = 0,
    .weave_amplitude = 0,
    .aggregate_amplitude = 0.12f,
    .pits = {PitGrid{1.5e-3, 0.1f, 1e-4f, 3.5e-4f, 0.6f},
             PitGrid{6e-3, 0.2f, 3.5e-4f, 1.2e-3f, 0.75f}},
    .scratches = {ScratchGrid{0.05, 0.05f, 1e-4f, 4e-4f, 1.0f, true, 0.5f, 0.08f}, ScratchGrid{}},
    .joint_style = JointStyle::kGap,
    .joint_half_width_m = 0.007f,
    .joint_band_half_width_m = 0.03f,
    .joint_albedo = 0.08f,
    .joint_band_delta = -0.06f,
    .text_albedo = 0.85f,
    .ring_albedo = 0.8f,
    .specular_base = 0.03f,
    .specular_bare = 0.05f,
    .specular_rust = 0.03f,
    .specular_paint = 0.08f,
};

// Fibre winding: bundles at +-55 degrees to the axis (the usual winding angle), 0.5 mm across and
// correlated over ~6 mm along.
constexpr double kWeaveAcrossM = 5e-4;
constexpr double kWeaveAlongM = 6e-3;
constexpr double kWeaveTan = 0.7002;  // tan(35 deg): fibre direction from the circumference

// Per-section random numbers: salts for Hash(section_seed + salt) and the lanes' seeds.
constexpr std::uint32_t kOctaveStride = 0x632BE5ABU;
constexpr std::uint32_t kSaltRust = 11;
constexpr std::uint32_t kSaltMarkingAngle = 12;
constexpr std::uint32_t kSaltWeldPhase = 13;
constexpr std::uint32_t kSaltPits = 0x1000;
constexpr std::uint32_t kSaltScratches = 0x2000;
constexpr std::uint32_t kSaltWeave = 0x3000;

LaneTable MakeLaneTable(const MaterialLook& look) {
  LaneTable table{};
  for (int k = 0; k < look.num_octaves; ++k) {
    const double cell = kCoarsestCellM * std::pow(kFinestCellM / kCoarsestCellM,
                                                  static_cast<double>(k) / (look.num_octaves - 1));
    table.inv_along[k] = table.inv_around[k] = 1 / cell;
    table.size_m[k] = cell;
    table.salt[k] = static_cast<std::uint32_t>(k) * kOctaveStride;
    table.stain_amplitude[k] = look.octave_amplitude[k];
    table.fine_amplitude[k] = cell <= kFineCellM ? look.octave_amplitude[k] : 0;
  }
  if (look.weave_amplitude > 0) {
    for (int family = 0; family < 2; ++family) {
      const int k = kWeaveLane + family;
      table.inv_along[k] = 1 / kWeaveAcrossM;
      table.inv_around[k] = 1 / kWeaveAlongM;
      table.shear_per_m[k] = (family == 0 ? 1 : -1) * kWeaveTan / kWeaveAcrossM;
      table.size_m[k] = 0.8 * kWeaveAcrossM;
      table.salt[k] = kSaltWeave + family;
    }
  }
  for (int g = 0; g < 2; ++g) {
    // An unused grid (cell 0) gets one cell; its probability 0 keeps it empty.
    const auto inverse = [](double cell_m) { return cell_m > 0 ? 1 / cell_m : 0.0; };
    table.inv_cell[kPitLane + g] = inverse(look.pits[g].cell_m);
    table.cell_salt[kPitLane + g] = kSaltPits + g;
    table.inv_cell[kScratchLane + g] = inverse(look.scratches[g].cell_m);
    table.cell_salt[kScratchLane + g] = kSaltScratches + g;
  }
  return table;
}

// Indexed by WallMaterial.
constexpr std::array<const MaterialLook*, 3> kLooks = {&kSteelLook, &kFiberglassLook,
                                                       &kConcreteLook};

const MaterialLook& LookOf(WallMaterial material) { return *kLooks[static_cast<int>(material)]; }

// Built on first use (std::pow is not constexpr), so safe from other static initialisers.
const LaneTable& LanesOf(WallMaterial material) {
  static const std::array<LaneTable, 3> tables = {
      MakeLaneTable(kSteelLook), MakeLaneTable(kFiberglassLook), MakeLaneTable(kConcreteLook)};
  return tables[static_cast<int>(material)];
}

// ---------------------------------------------------------------------------------------------
// Pits and scratches, given their lane's cell hash and position in the cell.

// Darkness in [0, 1] (times the grid's darkness) of the pit covering the point, or 0.
inline float PitDarkness(const PitGrid& grid, std::uint32_t cell_hash, float cell_x, float cell_y,
                         float footprint_m, float density) {
  const float presence = Uniform(cell_hash);
  const float probability = grid.probability * density;
  if (presence >= probability) return 0;
  const std::uint32_t shape = Hash(cell_hash + 1);
  const float size = LowUniform(shape);
  const float radius = grid.radius_min_m + (grid.radius_max_m - grid.radius_min_m) * size * size;
  // A pit narrower than a footprint is dropped; the edge softens to half a footprint.
  const float keep = SmoothStep(0.5f, 1.0f, radius / footprint_m);
  if (keep <= 0) return 0;
  const auto cell_m = static_cast<float>(grid.cell_m);
  const float margin = 2 * radius;  // covers radius + edge while keep > 0
  const float dh = cell_x * cell_m - (margin + (cell_m - 2 * margin) * HighUniform(shape));
  const std::uint32_t place = Hash(cell_hash + 2);
  const float ds = cell_y * cell_m - (margin + (cell_m - 2 * margin) * LowUniform(place));
  const float distance_sq = dh * dh + ds * ds;
  if (distance_sq >= margin * margin) return 0;
  const float distance = std::sqrt(distance_sq);
  const float edge = 0.5f * std::max(footprint_m, 0.2f * radius);
  // Soft presence: a pit fades in as the smooth density rises past its threshold, so a density
  // change never cuts a pit in half. Deeper towards the centre.
  const float appear = Clamp01((probability - presence) / (0.2f * probability + 1e-6f));
  const float depth = 0.75f + 0.25f * Clamp01(1 - distance / radius);
  return appear * keep * depth * (1 - SmoothStep(radius - edge, radius + edge, distance)) *
         grid.darkness;
}

// Signed albedo change of the scratch covering the point (positive for bright ones), or 0.
inline float ScratchValue(const ScratchGrid& grid, std::uint32_t cell_hash, float cell_x,
                          float cell_y, float footprint_m) {
  if (Uniform(cell_hash) >= grid.probability) return 0;
  const std::uint32_t shape = Hash(cell_hash + 1);
  const float width = grid.width_min_m + (grid.width_max_m - grid.width_min_m) * LowUniform(shape);
  // Blurring by the footprint widens the line and keeps its integral (area averaging); once the
  // blurred line would leave the cell margin it fades out.
  const float blurred_sq = width * width + footprint_m * footprint_m;
  if (blurred_sq >= kScratchMarginM * kScratchMarginM) return 0;
  // Direction (1, slope) normalised; a circumferential one is laid out as an axial one with the
  // axes swapped.
  const float slope = (2 * HighUniform(shape) - 1) * grid.max_slope;
  const float inv_norm = 1 / std::sqrt(1 + slope * slope);
  const float dir_h = inv_norm;
  const float dir_s = slope * inv_norm;
  const auto cell_m = static_cast<float>(grid.cell_m);
  float local_h = cell_x * cell_m;
  float local_s = cell_y * cell_m;
  if (grid.any_direction && (cell_hash & 1U) != 0) std::swap(local_h, local_s);
  const std::uint32_t place = Hash(cell_hash + 2);
  const float max_half = (0.5f * cell_m - kScratchMarginM) / inv_norm;
  const float half = max_half * (0.2f + 0.8f * LowUniform(place));
  const float extent_major = half * inv_norm + kScratchMarginM;
  const float extent_minor = half * std::abs(slope) * inv_norm + kScratchMarginM;
  const std::uint32_t extra = Hash(cell_hash + 3);
  const float ph = local_h - (extent_major + (cell_m - 2 * extent_major) * HighUniform(place));
  const float ps = local_s - (extent_minor + (cell_m - 2 * extent_minor) * LowUniform(extra));
  const float t = std::min(half, std::max(-half, ph * dir_h + ps * dir_s));
  const float qh = ph - t * dir_h;
  const float qs = ps - t * dir_s;
  const float distance_sq = qh * qh + qs * qs;
  if (distance_sq >= blurred_sq) return 0;
  const float blurred = std::sqrt(blurred_sq);
  const float keep = 1 - SmoothStep(0.5f * kScratchMarginM, kScratchMarginM, blurred);
  const float along = t / half;
  const float taper = 1 - along * along;  // scratches fade in and out along their length
  const float sign = HighUniform(extra) < grid.bright_fraction ? 1.0f : -1.0f;
  return sign * grid.amplitude * keep * taper * (width / blurred) *
         (1 - SmoothStep(0, blurred, std::sqrt(distance_sq)));
}

// ---------------------------------------------------------------------------------------------
// Markings: ring band, stencil text, arrow. Lengths in letter heights.

constexpr double kMarkingOriginFraction = 0.3;  // marking k starts at (k + 0.3) * spacing
constexpr double kRingBegin = -1.5;
constexpr double kRingEnd = -0.5;
constexpr double kArrowGap = 0.5;
constexpr double kArrowLength = 3.0;
constexpr double kMarkingLead = 2.0;  // the nearest marking is sought from 2 letters ahead

// Glyph atlas: cells of kGlyphWidth x kGlyphHeight texels, the capital letters filling
// kCapFraction of the height; the advance is the cell width (monospaced stencil).
constexpr int kGlyphWidth = 64;
constexpr int kGlyphHeight = 128;
constexpr double kCapFraction = 0.66;
constexpr char kGlyphChars[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-/.";
constexpr float kPaintEdgeM = 3e-4f;              // sprayed paint edges are not sharper than this
constexpr double kAdvance = 0.5 / kCapFraction;   // glyph advance in letter heights
constexpr double kHalfCell = 0.5 / kCapFraction;  // half the glyph cell height, in letters
constexpr int kMaxTextChars = 14;
// End of the longest marking, in letter heights after its origin.
constexpr double kMarkingEnd = kMaxTextChars * kAdvance + kArrowGap + kArrowLength + 0.2;

struct MarkingText {
  char chars[24];
  int length;
};

void AppendNumber(long long value, int min_digits, MarkingText* text) {
  char digits[20];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value > 0 && n < 20);
  while (n < min_digits) digits[n++] = '0';
  while (n > 0 && text->length < 23) text->chars[text->length++] = digits[--n];
}

// "DN<nominal diameter in mm, to 50> <section letter>-<4-digit marking number>".
MarkingText MakeMarkingText(int section, int index, double circumference_m) {
  MarkingText text{};
  text.chars[text.length++] = 'D';
  text.chars[text.length++] = 'N';
  const double diameter_mm = circumference_m / kTwoPi * 2 * 1000;
  AppendNumber(std::max(50LL, std::llround(diameter_mm / 50) * 50), 1, &text);
  text.chars[text.length++] = ' ';
  text.chars[text.length++] = static_cast<char>('A' + ((section % 26) + 26) % 26);
  text.chars[text.length++] = '-';
  AppendNumber(((index % 10000) + 10000) % 10000, 4, &text);
  text.chars[text.length] = '\0';
  return text;
}

// Footprint used by Specularity(), which has none.
constexpr double kSpecularFootprintM = 2.5e-4;
constexpr double kMinFootprintM = 1e-6;
constexpr double kMinCircumferenceM = 1e-3;

inline std::uint32_t SectionSeed(std::uint32_t seed_hash, int section) {
  return Hash(seed_hash + static_cast<std::uint32_t>(section) * 0x9E3779B9U);
}

// ---------------------------------------------------------------------------------------------
// The layers WallTexture::Sample composes, in its order.

// Where the texture is sampled: h, u = s / C in [0, 1), the circumference, the footprint (as
// double and float) and the section's seed.
struct SamplePoint {
  double h_m;
  double u;
  double circumference;
  double footprint;
  float fp;
  std::uint32_t section_seed;
};

// The albedo and specularity being composed, and how densely pits gather.
struct SurfaceLayers {
  float albedo;
  float specular;
  float density = 1;
};

// Rust blotches: a soft threshold on the low octaves; each section rusts to its own degree.
void AddRust(const MaterialLook& look, const LaneResult& lanes, const SamplePoint& point,
             SurfaceLayers* layers) {
  const std::array<float, kNumNoiseLanes>& n = lanes.noise;
  const float field = 0.5f * n[0] + 0.8f * n[1] + 0.9f * n[2] + 0.5f * n[3] + 0.25f * n[4];
  const float threshold =
      look.rust_threshold + 0.4f * (Uniform(Hash(point.section_seed + kSaltRust)) - 0.5f);
  const float soft = 0.05f + 60 * point.fp;
  const float rust = SmoothStep(threshold - soft, threshold + soft, field);
  layers->albedo =
      Lerp(layers->albedo, look.rust_albedo + 0.5f * lanes.stain + look.rust_roughness * lanes.fine,
           rust);
  layers->specular = Lerp(layers->specular, look.specular_rust, rust);
  layers->density = 0.4f + 2.5f * rust;  // corrosion pits gather in the rust
}

// Filament winding (two helical families of anisotropic noise) and aggregate speckle (light and
// dark grains where the millimetre octaves peak).
void AddWeaveAndAggregate(const MaterialLook& look, const LaneTable& table, const LaneResult& lanes,
                          const SamplePoint& point, SurfaceLayers* layers) {
  const std::array<float, kNumNoiseLanes>& n = lanes.noise;
  if (look.weave_amplitude > 0)
    layers->albedo += look.weave_amplitude * (n[kWeaveLane] + n[kWeaveLane + 1]);
  if (look.aggregate_amplitude > 0) {
    const float field = n[4] + 0.6f * n[5];
    const float soft = 0.08f + 0.5f * point.fp * static_cast<float>(table.inv_along[4]);
    const float grains = SmoothStep(0.35f - soft, 0.35f + soft, field) -
                         0.6f * SmoothStep(0.4f - soft, 0.4f + soft, -field);
    layers->albedo += look.aggregate_amplitude * grains;
    layers->density *= 1 + 0.8f * n[2];
  }
}

// Corrosion pits darken; scratches lighten or darken and bare the metal.
void AddPitsAndScratches(const MaterialLook& look, const LaneResult& lanes,
                         const SamplePoint& point, SurfaceLayers* layers) {
  for (int g = 0; g < 2; ++g) {
    const int lane = kPitLane + g;
    const float pit = PitDarkness(look.pits[g], lanes.cell_hash[lane], lanes.cell_x[lane],
                                  lanes.cell_y[lane], point.fp, layers->density);
    layers->albedo *= 1 - pit;
    layers->specular *= 1 - 0.7f * pit;
  }
  for (int g = 0; g < 2; ++g) {
    const int lane = kScratchLane + g;
    const float scratch = ScratchValue(look.scratches[g], lanes.cell_hash[lane], lanes.cell_x[lane],
                                       lanes.cell_y[lane], point.fp);
    layers->albedo += scratch;
    if (scratch > 0) {
      layers->specular = Lerp(layers->specular, look.specular_bare,
                              Clamp01(scratch / look.scratches[g].amplitude));
    }
  }
}

// A joint at h = k * spacing (after the paint: a gap cuts through it): a girth weld, a bonded
// flange or a segment gap.
void AddJoint(const MaterialLook& look, const LaneResult& lanes, const SamplePoint& point,
              double spacing, double inv_spacing, SurfaceLayers* layers) {
  const auto dh = static_cast<float>(
      point.h_m - static_cast<double>(FloorToInt(point.h_m * inv_spacing + 0.5)) * spacing);
  const float reach =
      1.3f * look.joint_half_width_m + look.joint_band_half_width_m + 0.005f + point.fp;
  if (std::abs(dh) < reach) {
    const float edge = std::max(5e-4f, point.fp);
    const float band_edge = std::max(0.2f * look.joint_band_half_width_m, point.fp);
    switch (look.joint_style) {
      case JointStyle::kWeld: {
        // A girth weld: a bead of wandering width and position with ripples across it
        // (chevrons), heat tint beside it. Integer frequencies in u keep it periodic.
        const float phase = Uniform(Hash(point.section_seed + kSaltWeldPhase));
        const auto uf = static_cast<float>(point.u);
        constexpr auto kTwoPiF = static_cast<float>(kTwoPi);
        const float w0 = look.joint_half_width_m;
        const float wander = 0.25f * w0 * std::sin(kTwoPiF * (2 * uf + phase));
        const float width = w0 * (1 + 0.12f * std::sin(kTwoPiF * (3 * uf + 2 * phase)) +
                                  0.06f * std::sin(kTwoPiF * (7 * uf + 3 * phase)));
        const float d = std::abs(dh - wander);
        layers->albedo += look.joint_band_delta *
                          (1 - SmoothStep(width, width + look.joint_band_half_width_m, d));
        constexpr double kRipplePitchM = 1.2e-3;
        const double ripples = Truncate(point.circumference / kRipplePitchM + 0.5);
        const double ripple_phase = point.u * ripples;
        const float across = (dh - wander) / width;
        const float ripple =
            FootprintWeight(kRipplePitchM, 1 / point.footprint) *
            std::sin(kTwoPiF * static_cast<float>(ripple_phase - Truncate(ripple_phase)) +
                     kTwoPiF * 1.2f * across * across);
        const float bead = 1 - SmoothStep(width - edge, width + edge, d);
        const float bead_albedo = look.joint_albedo + 0.08f * ripple + 2.0f * lanes.fine +
                                  0.4f * lanes.stain - 0.05f * across * across;
        layers->albedo = Lerp(layers->albedo, bead_albedo, bead);
        layers->specular =
            Lerp(layers->specular, look.specular_bare * (0.6f + 0.25f * ripple), bead);
        break;
      }
      case JointStyle::kFlange: {
        // Bonded flange: a band of darker adhesive with a thin dark gap in the middle.
        const float d = std::abs(dh);
        layers->albedo +=
            look.joint_band_delta * (1 - SmoothStep(look.joint_band_half_width_m - band_edge,
                                                    look.joint_band_half_width_m + band_edge, d));
        const float gap =
            1 - SmoothStep(look.joint_half_width_m - edge, look.joint_half_width_m + edge, d);
        layers->albedo = Lerp(layers->albedo, look.joint_albedo, gap);
        break;
      }
      case JointStyle::kGap: {
        // Segment joint: a dark gap with ragged edges and a dirty, damp band around it.
        const float ragged = std::abs(dh + 0.008f * lanes.noise[2] + 0.002f * lanes.noise[3]);
        layers->albedo += look.joint_band_delta *
                          (1 - SmoothStep(look.joint_band_half_width_m - band_edge,
                                          look.joint_band_half_width_m + band_edge, ragged));
        const float gap =
            1 - SmoothStep(look.joint_half_width_m - edge, look.joint_half_width_m + edge, ragged);
        layers->albedo = Lerp(layers->albedo, look.joint_albedo + 0.3f * lanes.fine, gap);
        layers->specular = Lerp(layers->specular, 0.0f, gap);
        break;
      }
    }
  }
}

}  // namespace

WallMaterial WallMaterialFromName(const std::string& name) {
  if (name == "steel") return WallMaterial::kSteel;
  if (name == "fiberglass") return WallMaterial::kFiberglass;
  if (name == "concrete") return WallMaterial::kConcrete;
  throw InputError("unknown wall material '" + name + "' (valid: steel, fiberglass, concrete)");
}

std::string WallMaterialName(WallMaterial material) {
  switch (material) {
    case WallMaterial::kSteel:
      return "steel";
    case WallMaterial::kFiberglass:
      return "fiberglass";
    case WallMaterial::kConcrete:
      return "concrete";
  }
  return "steel";
}

WallTexture::WallTexture(const WallTextureOptions& options) : options_(options) {
  const auto check = [](double value, const char* key) {
    if (!std::isfinite(value) || value < 0) {
      throw InputError(std::string(key) + " must be a finite number >= 0, got " +
                       std::to_string(value));
    }
  };
  check(options.texture_contrast, "texture_contrast");
  check(options.joint_spacing_m, "joint_spacing_m");
  check(options.marking_spacing_m, "marking_spacing_m");
  contrast_ = static_cast<float>(options.texture_contrast);
  const std::uint64_t seed = options.seed;
  seed_hash_ = Hash(static_cast<std::uint32_t>(seed) ^
                    Hash(static_cast<std::uint32_t>(seed >> 32) + 0x51ED270BU));
  inv_joint_spacing_ = options.joint_spacing_m > 0 ? 1 / options.joint_spacing_m : 0;
  inv_marking_spacing_ = options.marking_spacing_m > 0 ? 1 / options.marking_spacing_m : 0;
  max_letter_m_ = options.marking_spacing_m / (kMarkingLead + kMarkingEnd + 0.5);
  // PIPESCOPE_WALL_TEXTURE_SCALAR forces the scalar lanes, so tests can check both paths agree.
  use_avx2_ = CpuHasAvx2() && std::getenv("PIPESCOPE_WALL_TEXTURE_SCALAR") == nullptr;
  BuildGlyphAtlas();
}

void WallTexture::BuildGlyphAtlas() {
  std::fill(std::begin(glyph_of_char_), std::end(glyph_of_char_), -1);
  const int num_glyphs = static_cast<int>(sizeof(kGlyphChars)) - 1;
  // Rendered at twice the resolution and area-averaged down, so edges are anti-aliased.
  constexpr int kSuper = 2;
  const int canvas_height = kGlyphHeight * kSuper;
  const int font = cv::FONT_HERSHEY_DUPLEX;
  int baseline = 0;
  const cv::Size unit = cv::getTextSize("H", font, 1.0, 1, &baseline);
  const double scale = kCapFraction * canvas_height / unit.height;
  const int thickness = std::max(1, static_cast<int>(0.09 * kCapFraction * canvas_height));
  const cv::Size cap = cv::getTextSize("H", font, scale, thickness, &baseline);

  GlyphLevel level0;
  level0.width = kGlyphWidth;
  level0.height = kGlyphHeight;
  level0.coverage.assign(static_cast<std::size_t>(num_glyphs) * kGlyphWidth * kGlyphHeight, 0);
  for (int g = 0; g < num_glyphs; ++g) {
    glyph_of_char_[static_cast<unsigned char>(kGlyphChars[g])] = g;
    const std::string text(1, kGlyphChars[g]);
    const cv::Size size = cv::getTextSize(text, font, scale, thickness, &baseline);
    // Stencil lettering is condensed: 1.5 canvas heights wide squeezed into half a height; wide
    // letters get squeezed a little more.
    const int canvas_width = std::max(3 * canvas_height / 4, size.width + 2 * thickness);
    cv::Mat canvas(canvas_height, canvas_width, CV_8U, cv::Scalar(0));
    const cv::Point origin((canvas_width - size.width) / 2, (canvas_height + cap.height) / 2);
    cv::putText(canvas, text, origin, font, scale, cv::Scalar(255), thickness, cv::LINE_AA);
    cv::Mat glyph;
    canvas.convertTo(glyph, CV_32F, 1.0 / 255);
    cv::resize(glyph, glyph, cv::Size(kGlyphWidth, kGlyphHeight), 0, 0, cv::INTER_AREA);
    std::copy(
        glyph.ptr<float>(), glyph.ptr<float>() + kGlyphWidth * kGlyphHeight,
        level0.coverage.begin() + static_cast<std::ptrdiff_t>(g) * kGlyphWidth * kGlyphHeight);
  }
  glyph_levels_.push_back(std::move(level0));
  // Mip pyramid: 2x2 box averages per glyph, down to a single texel column.
  while (glyph_levels_.back().width > 1) {
    const GlyphLevel& fine = glyph_levels_.back();
    GlyphLevel coarse;
    coarse.width = fine.width / 2;
    coarse.height = fine.height / 2;
    coarse.coverage.resize(static_cast<std::size_t>(num_glyphs) * coarse.width * coarse.height);
    for (int row = 0; row < num_glyphs * coarse.height; ++row) {
      const float* top = &fine.coverage[static_cast<std::size_t>(2 * row) * fine.width];
      const float* bottom = top + fine.width;
      float* out = &coarse.coverage[static_cast<std::size_t>(row) * coarse.width];
      for (int col = 0; col < coarse.width; ++col) {
        out[col] =
            0.25f * (top[2 * col] + top[2 * col + 1] + bottom[2 * col] + bottom[2 * col + 1]);
      }
    }
    glyph_levels_.push_back(std::move(coarse));
  }
}

float WallTexture::GlyphCoverage(int glyph, float x, float y, float footprint_texels) const {
  const auto bilinear = [&](int level_index, float lx, float ly) {
    const GlyphLevel& level = glyph_levels_[level_index];
    const float scale = 1.0f / static_cast<float>(1 << level_index);
    // Texel centres of level l sit at (i + 0.5) * 2^l - 0.5 in level-0 texels.
    const float fx =
        std::min(std::max((lx + 0.5f) * scale - 0.5f, 0.0f), static_cast<float>(level.width - 1));
    const float fy =
        std::min(std::max((ly + 0.5f) * scale - 0.5f, 0.0f), static_cast<float>(level.height - 1));
    const int x0 = static_cast<int>(fx);
    const int y0 = static_cast<int>(fy);
    const int x1 = std::min(x0 + 1, level.width - 1);
    const int y1 = std::min(y0 + 1, level.height - 1);
    const float tx = fx - static_cast<float>(x0);
    const float ty = fy - static_cast<float>(y0);
    const float* cell =
        &level.coverage[static_cast<std::size_t>(glyph) * level.width * level.height];
    const float top = Lerp(cell[y0 * level.width + x0], cell[y0 * level.width + x1], tx);
    const float bottom = Lerp(cell[y1 * level.width + x0], cell[y1 * level.width + x1], tx);
    return Lerp(top, bottom, ty);
  };
  const int max_level = static_cast<int>(glyph_levels_.size()) - 1;
  // Trilinear: the level whose texels match the footprint.
  const float lod = std::log2(std::max(footprint_texels, 1.0f));
  const int level = std::min(static_cast<int>(lod), max_level);
  float coverage = bilinear(level, x, y);
  if (level < max_level) {
    coverage = Lerp(coverage, bilinear(level + 1, x, y), lod - static_cast<float>(level));
  }
  return coverage;
}

float WallTexture::MarkingCoverage(int section, std::int64_t index, double rel, double ds,
                                   double circumference_m, double letter_m, double footprint_m,
                                   float* paint_albedo) const {
  const MaterialLook& look = LookOf(options_.material);
  const auto fp = static_cast<float>(footprint_m / letter_m);  // in letter heights
  const float edge = std::max(0.5f * fp, static_cast<float>(kPaintEdgeM / letter_m));
  // Ring band, all around.
  if (rel < kRingEnd + 0.2) {
    *paint_albedo = look.ring_albedo;
    const auto r = static_cast<float>(rel);
    const float ring_edge = std::max(edge, static_cast<float>(1e-3 / letter_m));
    return SmoothStep(-ring_edge, ring_edge, r - static_cast<float>(kRingBegin)) *
           (1 - SmoothStep(-ring_edge, ring_edge, r - static_cast<float>(kRingEnd)));
  }
  // Text and arrow.
  const double half_cell = kHalfCell;
  *paint_albedo = look.text_albedo;
  const MarkingText text = MakeMarkingText(section, static_cast<int>(index), circumference_m);
  const double text_end = text.length * kAdvance;
  if (rel < text_end) {
    if (rel < 0) return 0;
    const int position = std::min(static_cast<int>(rel / kAdvance), text.length - 1);
    const int glyph = glyph_of_char_[static_cast<unsigned char>(text.chars[position])];
    if (glyph < 0) return 0;
    const auto x = static_cast<float>((rel - position * kAdvance) / kAdvance * kGlyphWidth - 0.5);
    const auto y = static_cast<float>((half_cell - ds) / (2 * half_cell) * kGlyphHeight - 0.5);
    const double texel = 2 * half_cell / kGlyphHeight;  // in letter heights
    const auto footprint_texels = static_cast<float>(fp / texel);
    const float coverage = GlyphCoverage(glyph, x, y, footprint_texels);
    // Magnified, bilinear edges would be a texel wide; sharpen them to the footprint (or the
    // spray's softness), the way a signed-distance font would.
    const float edge_texels =
        std::max(footprint_texels, static_cast<float>(kPaintEdgeM / letter_m / texel));
    const float gain = std::max(1.0f, 1.0f / edge_texels);
    return Clamp01((coverage - 0.5f) * gain + 0.5f);
  }
  // Arrow: a shaft of 2 letters and a head of 1, pointing along +h; signed distance, negative
  // inside.
  const auto a = static_cast<float>(rel - text_end - kArrowGap);
  const auto d = static_cast<float>(std::abs(ds));
  const float shaft = std::max(std::abs(a - 1.0f) - 1.0f, d - 0.18f);
  const float head = std::max(2.0f - a, (d + 0.5f * a - 1.5f) * 0.894f);
  return 1 - SmoothStep(-edge, edge, std::min(shaft, head));
}

WallMarking WallTexture::Marking(int section, int index, double circumference_m) const {
  const double circumference = std::max(circumference_m, kMinCircumferenceM);
  const double letter = std::min(LetterHeight(circumference), max_letter_m_);
  const double origin = (index + kMarkingOriginFraction) * options_.marking_spacing_m;
  const MarkingText text = MakeMarkingText(section, index, circumference);
  const std::uint32_t section_seed = SectionSeed(seed_hash_, section);
  WallMarking marking;
  marking.band_h_begin_m = origin + kRingBegin * letter;
  marking.band_h_end_m = origin + kRingEnd * letter;
  marking.text_h_begin_m = origin;
  marking.text_h_end_m = origin + text.length * kAdvance * letter;
  marking.arrow_h_end_m = marking.text_h_end_m + (kArrowGap + kArrowLength) * letter;
  marking.s_center_m = Uniform(Hash(section_seed + kSaltMarkingAngle)) * circumference;
  marking.letter_height_m = letter;
  marking.text = text.chars;
  return marking;
}

float WallTexture::Albedo(int section, double h_m, double s_m, double circumference_m,
                          double footprint_m) const {
  return Sample(section, h_m, s_m, circumference_m, footprint_m).albedo;
}

float WallTexture::Specularity(int section, double h_m, double s_m, double circumference_m) const {
  return Sample(section, h_m, s_m, circumference_m, kSpecularFootprintM).specularity;
}

WallSample WallTexture::BaseSample() const {
  const MaterialLook& look = LookOf(options_.material);
  return {look.base_albedo, look.specular_base};
}

WallSample WallTexture::Sample(int section, double h_m, double s_m, double circumference_m,
                               double footprint_m) const {
  const MaterialLook& look = LookOf(options_.material);
  if (contrast_ == 0) return {look.base_albedo, look.specular_base};
  const double circumference = std::max(circumference_m, kMinCircumferenceM);
  const double footprint = std::max(footprint_m, kMinFootprintM);
  const auto fp = static_cast<float>(footprint);
  const LaneTable& table = LanesOf(options_.material);
  const LaneGeometry& geometry = GeometryFor(table, circumference);
  // u = s / C in [0, 1): every layer below is periodic in u.
  double u = s_m * geometry.inv_circumference_m;
  u -= static_cast<double>(FloorToInt(u));
  if (u >= 1) u = 0;
  const std::uint32_t section_seed = SectionSeed(seed_hash_, section);

  LaneResult lanes;
  const LaneQuery query{h_m, u, 1 / footprint, section_seed, &geometry};
#ifdef PIPESCOPE_WALL_TEXTURE_AVX2
  if (use_avx2_) {
    EvaluateLanesAvx2(table, query, &lanes);
  } else {
    EvaluateLanesScalar(table, query, &lanes);
  }
#else
  EvaluateLanesScalar(table, query, &lanes);
#endif
  const SamplePoint point{h_m, u, circumference, footprint, fp, section_seed};
  SurfaceLayers layers{look.base_albedo + lanes.stain, look.specular_base};
  if (look.rust_threshold < 10) AddRust(look, lanes, point, &layers);
  AddWeaveAndAggregate(look, table, lanes, point, &layers);
  AddPitsAndScratches(look, lanes, point, &layers);
  // Painted markings, slightly worn. The nearest marking is sought from kMarkingLead letters
  // ahead, so the whole marking lies within one period.
  if (inv_marking_spacing_ > 0) {
    const double spacing = options_.marking_spacing_m;
    // Letters shrink when the spacing is too short for a whole marking.
    const bool shrunk = geometry.letter_m > max_letter_m_;
    const double letter = shrunk ? max_letter_m_ : geometry.letter_m;
    const double inv_letter = shrunk ? 1 / max_letter_m_ : geometry.inv_letter_m;
    const double origin = kMarkingOriginFraction * spacing;
    const std::int64_t index =
        FloorToInt((h_m - origin + kMarkingLead * letter) * inv_marking_spacing_);
    const double rel = (h_m - origin - static_cast<double>(index) * spacing) * inv_letter;
    // The ring goes all around; text and arrow lie within half a glyph cell of the section's
    // marking angle.
    bool painted = rel > kRingBegin - 0.2 && rel < kMarkingEnd;
    double ds = 0;
    if (painted && rel > kRingEnd + 0.2) {
      double du = u - Uniform(Hash(section_seed + kSaltMarkingAngle));
      du -= static_cast<double>(FloorToInt(du + 0.5));
      ds = du * circumference * inv_letter;
      painted = std::abs(ds) <= kHalfCell;
    }
    if (painted) {
      float paint_albedo = 0;
      const float paint =
          MarkingCoverage(section, index, rel, ds, circumference, letter, footprint, &paint_albedo);
      if (paint > 0) {
        const float wear =
            1 - 0.7f * SmoothStep(0.25f, 0.6f, lanes.noise[3] + lanes.noise[4] + lanes.noise[5]);
        const float cover = paint * wear;
        layers.albedo = Lerp(layers.albedo, paint_albedo + 0.3f * lanes.fine, cover);
        layers.specular = Lerp(layers.specular, look.specular_paint, cover);
      }
    }
  }

  if (inv_joint_spacing_ > 0) {
    AddJoint(look, lanes, point, options_.joint_spacing_m, inv_joint_spacing_, &layers);
  }
  WallSample sample;
  sample.albedo = Clamp01(look.base_albedo + contrast_ * (layers.albedo - look.base_albedo));
  sample.specularity =
      Clamp01(look.specular_base + contrast_ * (layers.specular - look.specular_base));
  return sample;
}

}  // namespace pipescope
