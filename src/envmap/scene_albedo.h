#pragma once
// The mean albedo of what a plate shows, as its camera exposed for it. A reflected-light meter
// is calibrated (ISO 2720, K = 12.5) so that the average scene it exposes for reflects about
// 12.5 % of the light it receives, not the 18 % of a grey card; streets, foliage, asphalt and
// walls (0.05-0.4) average about that. The plate's mean luminance is the scene's under that
// albedo, so it fixes how bright the sky lighting the scene must have been.
namespace pluvia::envmap {

inline constexpr double kMeteredSceneAlbedo = 0.125;

}  // namespace pluvia::envmap
