// The closed-form drop transfer function D(theta) (Wang et al. 2006, Appendices A-C) against
// analytic answers and independent quadratures, and swept over the stiff cases: theta = 0 and
// pi, grazing incidence, the rainbow caustics, up to 50 terms, eta from 1.0001 to 2.5.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "independent_fresnel.h"
#include "optics/drop_transfer.h"
#include "optics/fresnel.h"

namespace pluvia::optics {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::vector<double> kEtas = {1.0001, 1.01, 1.2, 1.333, 1.7, 2.5};

using test::fresnelSineTangent;

// The angle (from the forward direction) of the k-th order rainbow by Descartes' minimum
// deviation: cos^2(gamma) = (eta^2 - 1) / (k (k + 2)) for k internal reflections.
double descartesRainbowTheta(int internalReflections, double eta) {
  const int k = internalReflections;
  const double gamma = std::acos(std::sqrt((eta * eta - 1.0) / (k * (k + 2.0))));
  const double beta = std::asin(std::sin(gamma) / eta);
  const double deviation = 2.0 * (gamma - beta) + k * (M_PI - 2.0 * beta);
  return std::abs(std::remainder(deviation, 2.0 * M_PI));
}

// theta of the densest bin of the table between two angles.
double peakTheta(const TransferTable& table, double fromDeg, double toDeg) {
  double best = -1.0, bestTheta = 0.0;
  for (size_t k = 0; k < table.density.size(); ++k) {
    const double theta = std::acos(-1.0 + (k + 0.5) * table.binWidthMu());
    if (theta > fromDeg * kDeg && theta < toDeg * kDeg && table.density[k] > best) {
      best = table.density[k];
      bestTheta = theta;
    }
  }
  return bestTheta;
}

TEST(Fresnel, PaperFormEqualsSPAverageAndAnIndependentForm) {
  for (double eta : kEtas) {
    for (double incidenceDeg = 0.5; incidenceDeg < 89.9; incidenceDeg += 0.7) {
      const double c = std::cos(incidenceDeg * kDeg);
      const double r = fresnelReflectance(c, eta);
      EXPECT_NEAR(r, fresnelReflectancePaperForm(c, eta), 1e-12) << eta << " " << incidenceDeg;
      EXPECT_NEAR(r, fresnelSineTangent(incidenceDeg * kDeg, eta), 1e-12)
          << eta << " " << incidenceDeg;
    }
    EXPECT_NEAR(fresnelReflectance(1.0, eta), std::pow((eta - 1.0) / (eta + 1.0), 2.0), 1e-15);
    EXPECT_DOUBLE_EQ(fresnelReflectance(0.0, eta), 1.0);  // grazing: finite, total
  }
  // From inside the denser medium past the critical angle: total internal reflection.
  EXPECT_DOUBLE_EQ(fresnelReflectance(std::cos(60.0 * kDeg), 1.0 / 1.333), 1.0);
}

TEST(DropTransfer, EnergyMatchesItsClosedFormAndTendsToOne) {
  // sum_{n<=N} w_n = R + T (1 - R^(N-1)) per ray, so the energy of N terms is
  // 1 - integral of T R^(N-1) over the disc; midpoint rule over b^2 with 200,000 cells.
  for (double eta : kEtas) {
    for (int terms : {1, 2, 9, 50}) {
      double missing = 0.0;
      const int cells = 200000;
      for (int i = 0; i < cells; ++i) {
        const double b2 = (i + 0.5) / cells;
        const double r = fresnelSineTangent(std::asin(std::sqrt(b2)), eta);
        missing += (terms == 1 ? 1.0 - r : (1.0 - r) * std::pow(r, terms - 1)) / cells;
      }
      const double energy = transferEnergy({eta, terms});
      EXPECT_NEAR(energy, 1.0 - missing, 2e-6) << "eta " << eta << " N " << terms;
      EXPECT_LE(energy, 1.0 + 1e-12);
    }
    EXPECT_GT(transferEnergy({eta, 50}), 0.999) << eta;
  }
}

TEST(DropTransfer, NineTermsHoldThePapersShareOfThePower) {
  // The paper: "the first nine xi_n's hold about 99.8 % of the full power". We find 99.98 %.
  const double nine = transferEnergy({1.333, 9});
  EXPECT_GT(nine, 0.998);
  EXPECT_LT(nine, 1.0);
  // Term by term: the reflection ~6.6 %, straight through ~88 %, the primary rainbow ~4.4 %.
  EXPECT_NEAR(termEnergy(1, 1.333), 0.0664, 5e-4);
  EXPECT_NEAR(termEnergy(2, 1.333), 0.8814, 5e-4);
  EXPECT_NEAR(termEnergy(3, 1.333), 0.0439, 5e-4);
}

TEST(DropTransfer, RainbowCausticsSitWhereDescartesPutsThem) {
  const TransferTable table = binTransfer({1.333, 9}, 4096);
  const double primary = peakTheta(table, 134.0, 142.0) / kDeg;
  const double secondary = peakTheta(table, 125.0, 133.0) / kDeg;
  EXPECT_GE(primary, 137.5);
  EXPECT_LE(primary, 138.2);
  EXPECT_GE(secondary, 129.0);
  EXPECT_LE(secondary, 130.0);
  // The caustic is at the minimum deviation; the bins there are ~0.05 degrees wide.
  EXPECT_NEAR(primary, descartesRainbowTheta(1, 1.333) / kDeg, 0.15);
  EXPECT_NEAR(secondary, descartesRainbowTheta(2, 1.333) / kDeg, 0.15);
  // Dispersion: red (lower eta) has the larger rainbow radius, i.e. the smaller theta.
  const double red = peakTheta(binTransfer({1.331, 9}, 4096), 134.0, 142.0);
  const double blue = peakTheta(binTransfer({1.338, 9}, 4096), 134.0, 142.0);
  EXPECT_LT(red, primary * kDeg);
  EXPECT_GT(blue, primary * kDeg);
}

TEST(DropTransfer, ReflectionTermIsRoverFourPi) {
  // n = 1 alone: theta = pi - 2 gamma and D = R(gamma) / (4 pi) (xi_1 = R / 4, Eq. 6).
  for (double thetaDeg : {5.0, 30.0, 90.0, 150.0, 179.0}) {
    const double gamma = (M_PI - thetaDeg * kDeg) / 2.0;
    EXPECT_NEAR(transferDensity(thetaDeg * kDeg, {1.333, 1}),
                fresnelSineTangent(gamma, 1.333) / (4.0 * M_PI), 1e-10)
        << thetaDeg;
  }
}

TEST(DropTransfer, PointwiseDensityAgreesWithTheBinnedTableAwayFromCaustics) {
  const DropOptics optics{1.333, 9};
  const TransferTable table = binTransfer(optics, 4096);
  for (double theta : {0.05, 0.3, 0.5, 1.0, 1.5, 2.0, 2.2, 2.6, 3.0}) {
    const double pointwise = transferDensity(theta, optics);
    EXPECT_NEAR(table.at(std::cos(theta)), pointwise, 1e-3 * pointwise + 1e-6) << theta;
  }
}

TEST(DropTransfer, ZonalCoefficientsAgreeWithTheTableIntegrated) {
  // d_l two ways: Gauss quadrature over gamma (transferZonal) and the binned table integrated
  // over mu: d_l = 2 pi integral D(mu) Y_l0(mu) d mu.
  const DropOptics optics{1.333, 9};
  const int order = 8;
  const std::vector<double> zonal = transferZonal(optics, order);
  const TransferTable table = binTransfer(optics, 8192);
  for (int l = 0; l <= order; ++l) {
    double sum = 0.0;
    for (size_t k = 0; k < table.density.size(); ++k) {
      const double mu = -1.0 + (k + 0.5) * table.binWidthMu();
      sum += table.density[k] * std::legendre(l, mu) * table.binWidthMu();
    }
    const double fromTable = 2.0 * M_PI * std::sqrt((2.0 * l + 1.0) / (4.0 * M_PI)) * sum;
    EXPECT_NEAR(zonal[size_t(l)], fromTable, 2e-4) << "l " << l;
  }
  EXPECT_NEAR(zonal[0] * std::sqrt(4.0 * M_PI), transferEnergy(optics), 1e-12);
}

TEST(DropTransfer, FiniteAndNonNegativeEverywhere) {
  for (double eta : kEtas) {
    for (int terms : {1, 9, 50}) {
      const DropOptics optics{eta, terms};
      const TransferTable table = binTransfer(optics, 2048);
      double tableEnergy = 0.0;
      for (double d : table.density) {
        ASSERT_TRUE(std::isfinite(d) && d >= 0.0) << eta << " " << terms;
        tableEnergy += d * 2.0 * M_PI * table.binWidthMu();
      }
      EXPECT_NEAR(tableEnergy, transferEnergy(optics), 1e-6) << eta << " " << terms;
      const double caustic = descartesRainbowTheta(1, std::max(eta, 1.0001));
      for (double theta : {0.0, 1e-12, 1e-4, caustic, M_PI / 2, M_PI - 1e-12, M_PI}) {
        const double d = transferDensity(theta, optics);
        EXPECT_TRUE(std::isfinite(d) && d >= 0.0) << eta << " " << terms << " theta " << theta;
      }
      for (double v : transferZonal(optics, 8)) EXPECT_TRUE(std::isfinite(v));
      for (double gamma : {0.0, 1e-9, M_PI / 4, M_PI / 2 - 1e-12, M_PI / 2}) {
        for (int n : {1, 2, 3, terms}) {
          EXPECT_TRUE(std::isfinite(termPower(n, gamma, eta)));
          EXPECT_TRUE(std::isfinite(termCosTheta(n, gamma, eta)));
        }
      }
    }
  }
}

TEST(DropTransfer, RejectsImpossibleOptics) {
  EXPECT_THROW(transferEnergy({1.0, 9}), std::invalid_argument);
  EXPECT_THROW(transferEnergy({0.7, 9}), std::invalid_argument);
  EXPECT_THROW(transferEnergy({std::nan(""), 9}), std::invalid_argument);
  EXPECT_THROW(transferEnergy({1.333, 0}), std::invalid_argument);
  EXPECT_THROW(binTransfer({1.333, 9}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace pluvia::optics
