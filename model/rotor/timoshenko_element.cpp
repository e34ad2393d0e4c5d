#include "model/rotor/timoshenko_element.hpp"

#include <array>
#include <cmath>

namespace amb::model::rotor {
namespace {

// 4-point Gauss-Legendre on [0, 1]: exact to degree 7, enough for products of the cubic
// displacement and quadratic rotation shape functions.
constexpr std::array<double, 4> k_gauss_xi{0.0694318442029737, 0.3300094782075719,
                                           0.6699905217924281, 0.9305681557970263};
constexpr std::array<double, 4> k_gauss_w{0.1739274225687269, 0.3260725774312731,
                                          0.3260725774312731, 0.1739274225687269};

// Coefficient of z^3 in each displacement shape function. The static Timoshenko solution
// gives psi = dw/dz + (phi L^2 / 2) a3, so the shear strain w' - psi is constant per DOF.
Row4 cubic_coefficients(double length_m, double phi) {
  const double l3 = length_m * length_m * length_m;
  const double d = 1.0 + phi;
  return Row4(2.0 / (d * l3), 1.0 / (d * length_m * length_m), -2.0 / (d * l3),
              1.0 / (d * length_m * length_m));
}

}  // namespace

ElementSection element_section(const BeamElement& e) {
  ElementSection s;
  const double ro = 0.5 * e.outer_diameter_m, ri = 0.5 * e.inner_diameter_m;
  s.area_m2 = M_PI * (ro * ro - ri * ri);
  s.second_moment_m4 = M_PI / 4.0 * (std::pow(ro, 4) - std::pow(ri, 4));
  // Hutchinson's shear coefficient for a hollow circular section (Cowper's form), m = ri/ro.
  const double nu = e.poisson_ratio, m = ro > 0.0 ? ri / ro : 0.0, m2 = m * m;
  const double a = (1.0 + m2) * (1.0 + m2);
  s.shear_factor = 6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2);
  const double shear_modulus = e.youngs_modulus_pa / (2.0 * (1.0 + nu));
  s.phi = e.structural && s.area_m2 > 0.0
              ? 12.0 * e.youngs_modulus_pa * s.second_moment_m4 /
                    (s.shear_factor * shear_modulus * s.area_m2 * e.length_m * e.length_m)
              : 0.0;
  return s;
}

Row4 displacement_shape(double xi, double l, double phi) {
  const double d = 1.0 + phi, x2 = xi * xi, x3 = x2 * xi;
  return Row4((1.0 + phi - phi * xi - 3.0 * x2 + 2.0 * x3) / d,
              l * (xi - 2.0 * x2 + x3 + 0.5 * phi * (xi - x2)) / d,
              (phi * xi + 3.0 * x2 - 2.0 * x3) / d,
              l * (-x2 + x3 - 0.5 * phi * (xi - x2)) / d);
}

Row4 rotation_shape(double xi, double l, double phi) {
  const double d = 1.0 + phi, x2 = xi * xi;
  // d/dz of displacement_shape plus the constant shear correction (phi L^2 / 2) a3.
  const Row4 dw((-phi - 6.0 * xi + 6.0 * x2) / (d * l),
                (1.0 - 4.0 * xi + 3.0 * x2 + 0.5 * phi * (1.0 - 2.0 * xi)) / d,
                (phi + 6.0 * xi - 6.0 * x2) / (d * l),
                (-2.0 * xi + 3.0 * x2 - 0.5 * phi * (1.0 - 2.0 * xi)) / d);
  return dw + 0.5 * phi * l * l * cubic_coefficients(l, phi);
}

ElementMatrices element_matrices(const BeamElement& e, double phi, bool with_stiffness) {
  const ElementSection s = element_section(e);
  const double l = e.length_m;
  const double shear_modulus = e.youngs_modulus_pa / (2.0 * (1.0 + e.poisson_ratio));
  ElementMatrices m;
  // Shear strain per DOF (constant along the element): gamma = w' - psi = -(phi L^2/2) a3.
  const Row4 gamma = -0.5 * phi * l * l * cubic_coefficients(l, phi);
  for (size_t g = 0; g < k_gauss_xi.size(); ++g) {
    const double xi = k_gauss_xi[g], w = k_gauss_w[g] * l;
    const Row4 nw = displacement_shape(xi, l, phi);
    const Row4 np = rotation_shape(xi, l, phi);
    // d psi / dz: differentiate the quadratic rotation shape numerically-free (closed form).
    const double d = 1.0 + phi;
    const Row4 dpsi((-6.0 + 12.0 * xi) / (d * l * l), (-4.0 + 6.0 * xi - phi) / (d * l),
                    (6.0 - 12.0 * xi) / (d * l * l), (-2.0 + 6.0 * xi + phi) / (d * l));
    m.mass += w * e.density_kg_m3 * (s.area_m2 * nw.transpose() * nw +
                                     s.second_moment_m4 * np.transpose() * np);
    m.polar += w * e.density_kg_m3 * 2.0 * s.second_moment_m4 * np.transpose() * np;
    if (with_stiffness) {
      m.stiffness += w * e.youngs_modulus_pa * s.second_moment_m4 * dpsi.transpose() * dpsi;
      m.stiffness += w * s.shear_factor * shear_modulus * s.area_m2 * gamma.transpose() * gamma;
    }
  }
  return m;
}

}  // namespace amb::model::rotor
