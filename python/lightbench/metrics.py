"""Error metrics on arrays: the C++ definitions the experiment log uses
(experiments/metrics.h), so a value computed here equals log.csv's:

    RMSE           = sqrt(mean((x - r)^2))
    relMSE         = mean((x - r)^2 / (r^2 + eps))        eps = 1e-2 (experiments' relmse_epsilon)
    relMSE trimmed = relMSE without the fraction (default 0.001) of pixels
                     whose error (the channel mean) is largest
    MAPE           = 100 mean(|x - r| / (|r| + eps))      in percent

over every pixel and RGB channel, or over crop = (x0, y0, x1, y1), the
half-open pixel rectangle [x0, x1) x [y0, y1).

Given the reference's per-pixel variance of the mean (a run folder's
SCENE__reference_variance.exr), rmse, relmse and relmse_trimmed are
corrected for the reference's noise as the log's *_corrected columns are:
each (x - r)^2 less that variance (the RMSE is then sqrt of the corrected
MSE, 0 if it is negative).
"""
import math

from . import _core

DEFAULT_EPSILON = 1e-2
DEFAULT_TRIM_FRACTION = 1e-3


def _metrics(image, reference, epsilon, crop, reference_variance=None, fraction=DEFAULT_TRIM_FRACTION):
    return _core.metrics(image, reference, float(epsilon), list(crop) if crop is not None else [], reference_variance,
                         float(fraction))


def rmse(image, reference, crop=None, reference_variance=None):
    m = _metrics(image, reference, DEFAULT_EPSILON, crop, reference_variance)
    return m[0] if reference_variance is None else math.sqrt(max(0.0, m[4]))


def relmse(image, reference, epsilon=DEFAULT_EPSILON, crop=None, reference_variance=None):
    m = _metrics(image, reference, epsilon, crop, reference_variance)
    return m[1] if reference_variance is None else m[5]


def relmse_trimmed(image, reference, fraction=DEFAULT_TRIM_FRACTION, epsilon=DEFAULT_EPSILON, crop=None,
                   reference_variance=None):
    m = _metrics(image, reference, epsilon, crop, reference_variance, fraction)
    return m[3] if reference_variance is None else m[6]


def mape(image, reference, epsilon=DEFAULT_EPSILON, crop=None):
    return _metrics(image, reference, epsilon, crop)[2]
