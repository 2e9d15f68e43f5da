#pragma once
// An unbiased estimate of 1/p for an event of unknown probability p that can
// be retried: the number N of independent trials up to and including the
// first success is geometric, P(N = n) = (1 − p)^(n−1) p, so E[N] = 1/p
// (Zeltner, Georgiev & Jakob 2020, §4.3, for specular manifold sampling: the
// event is "Newton's method from a random seed reaches this solution").
// Stopping at `maxTrials` returns maxTrials where N would be larger: the
// estimate's mean is then (1 − (1 − p)^M)/p, short of 1/p by (1 − p)^M/p —
// negligible when p ≫ 1/M, the whole estimate (M instead of 1/p) when p ≪ 1/M.
namespace lb {

template <class Trial>
int trialsUntilSuccess(Trial succeeds, int maxTrials) {
  int n = 1;
  while (n < maxTrials && !succeeds()) ++n;
  return n;
}

}  // namespace lb
