#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pipescope {

// The look of a pipe wall (issue 3): steel as in 000, fiberglass as in 001, concrete as in 003.
enum class WallMaterial { kSteel, kFiberglass, kConcrete };

// "steel" | "fiberglass" | "concrete"; anything else throws InputError naming the value and
// listing the valid names.
WallMaterial WallMaterialFromName(const std::string& name);
std::string WallMaterialName(WallMaterial material);

struct WallTextureOptions {
  WallMaterial material = WallMaterial::kSteel;
  // Scales every deviation from the material's base albedo (and base specularity): 0 gives a
  // uniform wall, 1 the material's nominal look; may exceed 1.
  double texture_contrast = 1.0;
  // Seeds every random feature; each section hashes its index with it.
  std::uint64_t seed = 1;
  // Weld seams (steel), flange joints (fiberglass) or segment joints (concrete, 003: 1.5 m) at
  // h = k * joint_spacing_m; 0 = none.
  double joint_spacing_m = 0;
  // A painted ring band, stencil text ("DN400 A-0012") and a flow arrow every so many metres
  // along each section, at a fixed angle per section; 0 = none. Letters are 6% of the
  // circumference (15 to 50 mm) high, smaller when the spacing is under 17 letter heights.
  double marking_spacing_m = 2.0;
};

// Albedo and specular reflectance of one wall point, both in [0, 1].
struct WallSample {
  float albedo = 0;
  float specularity = 0;
};

// Where a section's painted marking `index` lies, in the section's surface coordinates.
struct WallMarking {
  double band_h_begin_m = 0;  // painted ring band, all around the circumference
  double band_h_end_m = 0;
  double text_h_begin_m = 0;  // stencil text, reading along +h
  double text_h_end_m = 0;
  double arrow_h_end_m = 0;  // the arrow follows the text, pointing along +h
  double s_center_m = 0;     // centre line of text and arrow, in [0, circumference)
  double letter_height_m = 0;
  std::string text;
};

// Procedural wall texture in surface coordinates (h, s = r * phi) of each pipe section: h in
// metres along the section's centre line, s in metres around it, periodic with the
// circumference. Multi-scale stains and corrosion (gradient noise from 0.3 m down to 0.1 mm),
// rust blotches, pits, scratches, joints, painted markings and stencil lettering (001 §IV-B
// relies on the lettering). Values are low-pass filtered to a footprint (the size of a pixel on
// the wall), like a procedural mip-map, so far and grazing views do not alias.
//
// Deterministic: a pure function of the options and the arguments, so safe to call from any
// number of threads in any order; bit-identical with or without AVX2 (the lattice noise runs 8
// lanes at a time where the CPU has it; PIPESCOPE_WALL_TEXTURE_SCALAR in the environment at
// construction forces the scalar path). Costs about 70-90 ns per call at a 0.1 mm footprint on
// the 2-core development machine.
class WallTexture {
 public:
  // Throws InputError for a negative or non-finite texture_contrast or spacing.
  explicit WallTexture(const WallTextureOptions& options);

  // Albedo in [0, 1] at (h_m, s_m) of `section`, whose circumference is `circumference_m`,
  // filtered to `footprint_m`: features finer than about two footprints fade out.
  float Albedo(int section, double h_m, double s_m, double circumference_m,
               double footprint_m) const;

  // Specular reflectance in [0, 1] for the lighting model's highlight term: steel shiny (bare
  // metal in scratches, weld beads), rust and concrete matte, fiberglass glossy. Filtered to a
  // fixed 0.25 mm footprint.
  float Specularity(int section, double h_m, double s_m, double circumference_m) const;

  // Albedo and specularity at once, both filtered to `footprint_m`; costs about what Albedo()
  // costs, so a renderer wanting both should call this.
  WallSample Sample(int section, double h_m, double s_m, double circumference_m,
                    double footprint_m) const;

  // The material's base albedo and specularity, what a uniform wall (texture_contrast 0) shows
  // everywhere: the finish of a white card cut from this wall (000 §3.2).
  WallSample BaseSample() const;

  // Layout of marking `index` (at h near (index + 0.3) * marking_spacing_m) of `section`.
  // Only meaningful when marking_spacing_m > 0.
  WallMarking Marking(int section, int index, double circumference_m) const;

  const WallTextureOptions& options() const { return options_; }

 private:
  // One level of the glyph atlas mip pyramid: glyphs stacked vertically, each a width x height
  // cell of paint coverage in [0, 1].
  struct GlyphLevel {
    int width = 0;
    int height = 0;
    std::vector<float> coverage;
  };

  void BuildGlyphAtlas();
  // Paint coverage of glyph `glyph` at (x, y) in level-0 texels, filtered to `footprint_texels`.
  float GlyphCoverage(int glyph, float x, float y, float footprint_texels) const;
  // Paint coverage in [0, 1] of marking `index` at `rel` letter heights after its origin and
  // `ds` letter heights around from its centre line, and the paint's albedo.
  float MarkingCoverage(int section, std::int64_t index, double rel, double ds,
                        double circumference_m, double letter_m, double footprint_m,
                        float* paint_albedo) const;

  WallTextureOptions options_;
  float contrast_;
  std::uint32_t seed_hash_;
  double inv_joint_spacing_;    // 0 when there are no joints
  double inv_marking_spacing_;  // 0 when there are no markings
  double max_letter_m_;         // letter height that fits a whole marking in the spacing
  bool use_avx2_;               // lattice lanes go 8 at a time where the CPU allows
  std::vector<GlyphLevel> glyph_levels_;
  // Glyph index of each ASCII character, -1 for characters drawn as blanks.
  int glyph_of_char_[128];
};

}  // namespace pipescope
