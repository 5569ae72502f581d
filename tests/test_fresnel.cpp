// Dielectric Fresnel against closed forms; total internal reflection; Snell.
#include <gtest/gtest.h>

#include "core/fresnel.h"

namespace pl {
namespace {

TEST(Fresnel, NormalIncidence) {
    for (float eta : {1.0f, 1.33f, 1.5f, 2.5f, 1.0f / 1.5f}) {
        float r = (eta - 1) / (eta + 1);
        EXPECT_NEAR(fresnelDielectric(1.0f, eta), r * r, 1e-6f) << eta;
    }
}

TEST(Fresnel, IndexMatchedBoundaryIsInvisible) {
    for (float c : {0.01f, 0.3f, 0.7f, 1.0f}) EXPECT_NEAR(fresnelDielectric(c, 1.0f), 0.0f, 1e-7f);
}

TEST(Fresnel, BrewsterAngleLeavesOnlyThePerpendicularPart) {
    for (float eta : {1.5f, 2.5f}) {
        double thetaB = std::atan(double(eta));
        double ci = std::cos(thetaB), st = std::sin(thetaB) / eta, ct = std::sqrt(1 - st * st);
        double rs = (ci - eta * ct) / (ci + eta * ct);
        EXPECT_NEAR(fresnelDielectric(float(ci), eta), 0.5 * rs * rs, 1e-5);
    }
}

TEST(Fresnel, ClosedFormAtOblique45Degrees) {
    // eta = 1.5, theta_i = 45 deg: Rs and Rp from sin/tan forms of Fresnel's equations.
    double ti = kPi / 4, tt = std::asin(std::sin(ti) / 1.5);
    double rs = std::pow(std::sin(ti - tt) / std::sin(ti + tt), 2);
    double rp = std::pow(std::tan(ti - tt) / std::tan(ti + tt), 2);
    EXPECT_NEAR(fresnelDielectric(float(std::cos(ti)), 1.5f), 0.5 * (rs + rp), 1e-6);
}

TEST(Fresnel, TotalInternalReflectionBeyondCriticalAngle) {
    for (float ior : {1.5f, 2.5f}) {
        float eta = 1.0f / ior;  // from inside the resin towards air
        float cosCritical = std::sqrt(1 - eta * eta);
        EXPECT_EQ(fresnelDielectric(cosCritical * 0.999f, eta), 1.0f);
        EXPECT_EQ(fresnelDielectric(0.0f, eta), 1.0f);
        EXPECT_LT(fresnelDielectric(std::min(1.0f, cosCritical * 1.01f), eta), 1.0f);
        float c = 0.5f * cosCritical;
        Vec3f d(std::sqrt(1 - c * c), 0, -c);
        EXPECT_FALSE(refract(d, {0, 0, 1}, eta).has_value());
    }
}

TEST(Fresnel, ReciprocityAcrossTheBoundary) {
    for (float ci : {0.2f, 0.5f, 0.9f}) {
        float eta = 1.5f;
        float st = std::sqrt(1 - ci * ci) / eta, ct = std::sqrt(1 - st * st);
        EXPECT_NEAR(fresnelDielectric(ci, eta), fresnelDielectric(ct, 1 / eta), 1e-5f);
    }
}

TEST(Fresnel, RefractionObeysSnell) {
    Vec3f n(0, 0, 1);
    for (float angle : {0.0f, 0.3f, 0.8f, 1.4f}) {
        Vec3f d(std::sin(angle), 0, -std::cos(angle));
        auto t = refract(d, n, 1.5f);
        ASSERT_TRUE(t.has_value());
        EXPECT_NEAR(length(*t), 1.0f, 1e-6f);
        EXPECT_NEAR(std::sqrt(1 - t->z * t->z), std::sin(angle) / 1.5f, 1e-5f);
        EXPECT_LT(t->z, 0.0f);
        EXPECT_NEAR(t->y, 0.0f, 1e-7f);  // stays in the plane of incidence
    }
    Vec3f r = reflect(normalize(Vec3f(1, 0, -1)), n);
    EXPECT_NEAR(r.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(r.z, std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace pl
