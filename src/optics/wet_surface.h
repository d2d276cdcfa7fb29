#pragma once
// Why a rough surface is darker when wet (Lekner and Dorf 1988, "Why some things are darker when
// wet", Applied Optics 27(7), 1278): under a film of water of index n, light that the surface
// (albedo a, Lambertian) sends back up meets the water-air interface from inside, where a diffuse
// field is reflected back down with p = 1 - (1 - Rbar) / n^2 (Rbar: the interface's reflectance
// for diffuse light from outside, 0.066 for n = 1.333; p = 0.47): some of it is absorbed at the
// next bounce, so the surface loses more light the darker it is. Its albedo becomes
//   A = (1 - Rbar) (1 - p) a / (1 - p a),
// and seen along a direction at angle theta from the normal (outside), its radiance
//   L_wet(theta) = (1 - Rbar) (1 - R(theta)) a E / (pi n^2 (1 - p a))
// against the dry L = a E / pi (E: irradiance from outside, taken as diffuse; R(theta): Fresnel's),
// which averages over the hemisphere to A. The film's top face adds R(theta) times the light it
// mirrors (the gloss).
namespace pluvia::optics {

// Rbar: Fresnel's reflectance from outside (air, index 1) into index `eta`, averaged over a
// diffuse (cosine-weighted) hemisphere: 2 int R(theta) cos(theta) sin(theta) dtheta.
double diffuseFresnelReflectance(double eta);

struct WetFilm {
  double eta = 1.333;
  double externalDiffuse = 0.0;  // Rbar
  double internalDiffuse = 0.0;  // p = 1 - (1 - Rbar) / eta^2
};
WetFilm wetFilm(double eta);

// A, the wet albedo of a surface of dry albedo `albedo` (0..1).
double wetAlbedo(const WetFilm& film, double albedo);

// L_wet(theta) / L_dry: what the film does to the surface's own (diffuse) radiance seen at
// cos theta = `cosView` (0..1), without the gloss.
double wetRadianceRatio(const WetFilm& film, double albedo, double cosView);
// The same with Fresnel's reflectance R(theta) at the view angle given (made once per pixel of a
// camera that stays).
double wetRadianceRatioAt(const WetFilm& film, double albedo, double viewReflectance);

}  // namespace pluvia::optics
