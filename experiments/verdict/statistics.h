#pragma once
// The few distributions and tests the verdicts need (issue 32): Student's t
// (its CDF from the regularised incomplete beta function, its quantile by
// bisection on the CDF), Welch–Satterthwaite degrees of freedom, a two-sided
// t-test of a difference with a known standard error, Holm's step-down
// adjustment of p-values, and batch means.
//
// Nothing here knows about images or experiments: tests/experiments/verdict/
// checks it against closed forms (t with 1 and 2 degrees of freedom, where
// the CDF is elementary) and tabulated quantiles.
#include <vector>

namespace lb {

// I_x(a, b), the regularised incomplete beta function (continued fraction,
// modified Lentz's method; Press et al., Numerical Recipes, 3rd ed., §6.4).
double regularizedIncompleteBeta(double a, double b, double x);

// P(T ≤ t) for Student's t with `dof` degrees of freedom (> 0, not
// necessarily an integer; +∞ gives the normal distribution).
double studentTCdf(double t, double dof);
// The p-quantile, 0 < p < 1.
double studentTQuantile(double p, double dof);

// Welch–Satterthwaite: the degrees of freedom of a sum of independent
// variance estimates v_i with dof_i degrees of freedom each
// (Σ v_i)² / Σ (v_i² / dof_i). A term with dof_i = +∞ (a variance known
// exactly) adds nothing to the denominator; all zero: +∞.
double satterthwaiteDof(const std::vector<double>& variances, const std::vector<double>& dofs);

// Two-sided p-value of a difference d whose standard error is se, with dof
// degrees of freedom: 2 P(T > |d| / se). se = 0: 1 when d = 0, else 0; any
// NaN: 1 (nothing is decided on it).
double twoSidedP(double difference, double standardError, double dof);

// Holm (1979): the step-down adjusted p-values, in the input's order. A
// hypothesis is rejected at family-wise level α when its adjusted p < α.
std::vector<double> holmAdjust(const std::vector<double>& p);

// A weighted mean of batch means x_i (weights w_i ≥ 0, e.g. pixel counts of
// image tiles) and the variance of that mean, estimated from the spread of
// the batches (the ratio estimator's k/(k−1) Σ (w_i/W)² (x_i − mean)²),
// with k − 1 degrees of freedom over the k batches of non-zero weight.
struct BatchMeans {
  double mean = 0, varianceOfMean = 0, dof = 0;
  int batches = 0;
};
BatchMeans batchMeans(const std::vector<double>& sums, const std::vector<double>& weights);

}  // namespace lb
