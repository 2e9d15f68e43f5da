"""Error metrics on arrays: the C++ definitions the experiment log uses
(experiments/metrics.h), so a value computed here equals log.csv's:

    RMSE   = sqrt(mean((x - r)^2))
    relMSE = mean((x - r)^2 / (r^2 + eps))        eps = 1e-2 (experiments' relmse_epsilon)
    MAPE   = 100 mean(|x - r| / (|r| + eps))      in percent

over every pixel and RGB channel, or over crop = (x0, y0, x1, y1), the
half-open pixel rectangle [x0, x1) x [y0, y1).
"""
from . import _core

DEFAULT_EPSILON = 1e-2


def _metrics(image, reference, epsilon, crop):
    return _core.metrics(image, reference, float(epsilon), list(crop) if crop is not None else [])


def rmse(image, reference, crop=None):
    return _metrics(image, reference, DEFAULT_EPSILON, crop)[0]


def relmse(image, reference, epsilon=DEFAULT_EPSILON, crop=None):
    return _metrics(image, reference, epsilon, crop)[1]


def mape(image, reference, epsilon=DEFAULT_EPSILON, crop=None):
    return _metrics(image, reference, epsilon, crop)[2]
