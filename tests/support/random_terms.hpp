#pragma once
// Test support: random error terms of each form, of the sizes real machines show (tens of
// um, tens of urad), on random links and components of the kHmcChain machine.
#include <random>
#include <string>

namespace ccomp::test {

/// Four "terms:" lines of `form` (polynomial, table, periodic, reversal, thermal, warmup,
/// scale_expansion, cross_axis; anything else: location errors).
std::string random_terms(const std::string& form, std::mt19937& rng);

}  // namespace ccomp::test
