// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a speed/accuracy map is read by: its Pareto front and the exponent of a cost's growth.
//
// Front: the points (cost c_i, error e_i) that no other point beats on both, i.e. no j with
// c_j <= c_i and e_j <= e_i and one of them strictly less. Exponent: the least-squares slope p of
// log y = p log x + b, so y ~ x^p (cost per step against springs: p close to 1 is linear).

#include <vector>

namespace tissuesim {

/// The indices of the Pareto front of (cost, error), in increasing cost. Points whose cost or
/// error is not finite take no part. The two vectors have the same length. A costlier point
/// joins the front only when its error is more than `errorResolution` below every cheaper
/// one's: errors that differ by less than what they can be told apart by (a map's rows that
/// give the same forces to a few digits) are ties, and the cheaper point takes the place.
std::vector<int> paretoFront(const std::vector<double>& cost, const std::vector<double>& error,
                             double errorResolution = 0.0);

/// The slope of log y against log x by least squares over the pairs with x, y > 0 (finite);
/// NaN when fewer than two distinct x remain.
double powerLawExponent(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace tissuesim
