#pragma once
// Horizontal tropospheric gradients: the azimuthal asymmetry of the slant delay
// (Chen & Herring 1997, "Effects of atmospheric azimuthal asymmetry on the
// analysis of space geodetic data", JGR 102(B9), 20489-20502):
//
//   T(e, a) = m_h(e) ZHD + m_w(e) ZWD + m_g(e) (G_N cos a + G_E sin a),
//   m_g(e)  = 1 / (sin e tan e + C),  C = 0.0032,
//
// e the elevation, a the azimuth (from north, clockwise towards east), G_N and
// G_E the north and east gradients [m] (typically millimetres; Bar-Sever,
// Kroger & Borjesson 1998, JGR 103(B3)). m_g vanishes at zenith (tan e -> inf)
// and grows like the square of the cosecant towards the horizon (C keeps it
// finite there: 1 / C = 312.5 at e = 0).
// The partials d T / d G_N = m_g cos a and d T / d G_E = m_g sin a are constant
// in the gradients: the slant delay is linear in them.
namespace ppp {

/// Chen & Herring's constant C of the gradient mapping (the total delay's value, Chen & Herring 1997).
constexpr double kChenHerringGradientConstant = 0.0032;

/// Gradient mapping m_g(e) = 1 / (sin e tan e + 0.0032) (dimensionless).
double gradientMapping(double elevation_rad);

/// d(slant delay) / d(G_N, G_E) of a satellite at (elevation, azimuth).
struct GradientPartials {
  double north = 0.0;  // m_g(e) cos a
  double east = 0.0;   // m_g(e) sin a
};
GradientPartials gradientPartials(double elevation_rad, double azimuth_rad);

/// The gradients' share of the slant delay [m]: m_g(e) (G_N cos a + G_E sin a).
double slantGradientDelay_m(double elevation_rad, double azimuth_rad, double gradient_north_m,
                            double gradient_east_m);

}  // namespace ppp
