/*
 * driftlab's C runtime: the code every generated header shares, for a gyro's processor.
 *
 * A header is this runtime's sections, copied in between the tables and functions generated for
 * its calibration (the curves' constants, each model's predict, the sampling constants
 * DRIFTLAB_DT_S, DRIFTLAB_SMOOTH_SAMPLES, DRIFTLAB_STEP_SAMPLES, DRIFTLAB_RING_SAMPLES and
 * DRIFTLAB_TWO_H_S). A section runs from its begin marker to its end marker; the markers are
 * not copied. A header of one axis keeps the temperature's history inside its own state, so it
 * takes the inner sections (the fields, init and push statements) with t-> read as st->.
 *
 * Every section repeats driftlab's arithmetic operation for operation (see the module doc of
 * export::firmware::c_header): the curves are Approx::eval, the temperature's history is
 * signal::Rates' causal moving average and 3-point backward differences. Change them only with
 * the Rust they port, and run the tests that compile the headers and compare.
 */
/*@ begin curves */

/* ---- Curves: one coefficient as a function of one variable ---------------------------- */

/* The approximation the engineer chose (informational: evaluation follows the curve's form). */
#define DRIFTLAB_KIND_LINEAR 0
#define DRIFTLAB_KIND_PARABOLIC 1
#define DRIFTLAB_KIND_PWL 2
#define DRIFTLAB_KIND_SPLINE 3

/* A fitted curve. A polynomial is sum coeffs[k]*x^k (lowest power first, n coefficients). A
 * knot curve (piecewise-linear or Catmull-Rom through n knots) is, between knots i and i+1, the
 * cubic segments[i][0] + segments[i][1]*u + segments[i][2]*u^2 + segments[i][3]*u^3 with
 * u = (x - knots_x[i]) / (knots_x[i+1] - knots_x[i]), and beyond its end knots the straight line
 * through the end knot and its neighbour. Outside [x_min, x_max] the value at the nearer edge
 * is held, unless extrapolate is set. */
typedef struct {
    int kind;                    /* DRIFTLAB_KIND_* */
    int knot_curve;              /* 0: polynomial in coeffs; 1: knots and segments */
    int extrapolate;             /* 1: evaluate beyond [x_min, x_max]; 0: hold the edge value */
    double x_min, x_max;         /* range of the argument the curve was fitted on */
    size_t n;                    /* coefficients, or knots */
    const double *coeffs;        /* polynomial only */
    const double *knots_x;       /* knot curve only: strictly increasing */
    const double *knots_y;       /* knot curve only */
    const double (*segments)[4]; /* knot curve only: n - 1 cubics in u */
    double inv_step;             /* knot curve only: 1/spacing when equally spaced, else 0 */
} driftlab_curve;

static inline double driftlab_edge_line(double x0, double y0, double x1, double y1, double x)
{
    if (x == x0) {
        return y0;
    }
    return y0 + (y1 - y0) / (x1 - x0) * (x - x0);
}

/* The curve at x; 0 for a non-finite x (no correction from a sample without a rate). */
static inline double driftlab_curve_eval(const driftlab_curve *c, double x)
{
    if (!isfinite(x)) {
        return 0.0;
    }
    if (!c->extrapolate) {
        if (x < c->x_min) {
            x = c->x_min;
        }
        if (x > c->x_max) {
            x = c->x_max;
        }
    }
    if (!c->knot_curve) {
        size_t k = c->n - 1;
        double acc = c->coeffs[k];
        while (k > 0) {
            k--;
            acc = acc * x + c->coeffs[k];
        }
        return acc;
    } else {
        const double *kx = c->knots_x;
        const double *ky = c->knots_y;
        const double *s;
        size_t n = c->n, last = c->n - 2, i;
        double u;
        if (x <= kx[0]) {
            return driftlab_edge_line(kx[0], ky[0], kx[1], ky[1], x);
        }
        if (x >= kx[n - 1]) {
            return driftlab_edge_line(kx[n - 1], ky[n - 1], kx[n - 2], ky[n - 2], x);
        }
        if (c->inv_step > 0.0) {
            double f = (x - kx[0]) * c->inv_step; /* > 0 here */
            i = f >= (double)last ? last : (size_t)f;
        } else {
            i = 0;
            while (i < last && kx[i + 1] <= x) {
                i++;
            }
        }
        u = (x - kx[i]) / (kx[i + 1] - kx[i]);
        if (u < 0.0) {
            u = 0.0;
        }
        if (u > 1.0) {
            u = 1.0;
        }
        s = c->segments[i];
        return ((s[3] * u + s[2]) * u + s[1]) * u + s[0];
    }
}
/*@ end curves */
/*@ begin regimes */

/* ---- The Vakhrameev model: Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot ---------- */

/* Regimes, from the sign of Tdot*Tddot. */
#define DRIFTLAB_REGIME_STATIC 0 /* Tdot*Tddot = 0: K0 only */
#define DRIFTLAB_REGIME_PLUS 1   /* Tdot*Tddot > 0, thermal acceleration: K1+, K2+ */
#define DRIFTLAB_REGIME_MINUS 2  /* Tdot*Tddot < 0, thermal deceleration: K1-, K2- */
/*@ end regimes */
/*@ begin regime_fn */

/* The regime of a sample with these rates. */
static inline int driftlab_regime(double tdot_c_s, double tddot_c_s2)
{
    double p = tdot_c_s * tddot_c_s2;
    if (p > 0.0) {
        return DRIFTLAB_REGIME_PLUS;
    }
    if (p < 0.0) {
        return DRIFTLAB_REGIME_MINUS;
    }
    return DRIFTLAB_REGIME_STATIC;
}
/*@ end regime_fn */
/*@ begin beyond_fn */

/* 1 when x lies beyond the range c was fitted on. A term left out for want of points (the zero
 * polynomial over an empty range, x_min == x_max) adds nothing wherever x lies: no x is beyond
 * it, as driftlab judges it. */
static inline int driftlab_beyond(const driftlab_curve *c, double x)
{
    if (!c->knot_curve && c->x_min == c->x_max) {
        size_t k;
        for (k = 0; k < c->n; k++) {
            if (c->coeffs[k] != 0.0) {
                return x < c->x_min || x > c->x_max;
            }
        }
        return 0;
    }
    return x < c->x_min || x > c->x_max;
}
/*@ end beyond_fn */
/*@ begin temperature */

/* The temperature's history: smoothed once, differentiated once, for every Vakhrameev axis. */
typedef struct {
/*@ begin temperature_fields */
    double smooth_buf[DRIFTLAB_SMOOTH_SAMPLES]; /* the last raw temperatures, degC */
    double smooth_sum;                          /* their running sum */
    size_t smooth_next;                         /* slot of the next temperature */
    size_t smooth_filled;                       /* temperatures in the window */
    double temp_ring[DRIFTLAB_RING_SAMPLES];    /* smoothed T, degC */
    double tdot_ring[DRIFTLAB_RING_SAMPLES];    /* Tdot, degC/s */
    size_t slot;                                /* ring slot of the next sample */
    size_t history;                             /* samples seen, counted up to 4 * step */
/*@ end temperature_fields */
} driftlab_temperature;

/* Starts the temperature's history afresh. */
static inline void driftlab_temperature_init(driftlab_temperature *t)
{
/*@ begin temperature_init */
    size_t k;
    for (k = 0; k < DRIFTLAB_SMOOTH_SAMPLES; k++) {
        t->smooth_buf[k] = 0.0;
    }
    for (k = 0; k < DRIFTLAB_RING_SAMPLES; k++) {
        t->temp_ring[k] = 0.0;
        t->tdot_ring[k] = 0.0;
    }
    t->smooth_sum = 0.0;
    t->smooth_next = 0;
    t->smooth_filled = 0;
    t->slot = 0;
    t->history = 0;
/*@ end temperature_init */
}

/* Feeds one temperature (degC); Tdot (degC/s) and Tddot (degC/s^2) go to *tdot_out and
 * *tddot_out (0 while the history is too short). */
static inline void driftlab_temperature_push(driftlab_temperature *t, double temp_c,
                                             double *tdot_out, double *tddot_out)
{
/*@ begin temperature_rings */
    const size_t s = DRIFTLAB_STEP_SAMPLES, len = DRIFTLAB_RING_SAMPLES;
    const size_t slot = t->slot;
    const size_t back1 = slot >= s ? slot - s : slot + len - s;
    const size_t back2 = slot >= 2 * s ? slot - 2 * s : slot + len - 2 * s;
/*@ end temperature_rings */
    double ts, tdot, tddot;

/*@ begin temperature_push */
/*@ begin smoothing */
    /* Causal moving average of T over the last DRIFTLAB_SMOOTH_SAMPLES samples. */
    if (t->smooth_filled == DRIFTLAB_SMOOTH_SAMPLES) {
        t->smooth_sum -= t->smooth_buf[t->smooth_next];
    } else {
        t->smooth_filled++;
    }
    t->smooth_sum += temp_c;
    t->smooth_buf[t->smooth_next] = temp_c;
    t->smooth_next = t->smooth_next + 1 == DRIFTLAB_SMOOTH_SAMPLES ? 0 : t->smooth_next + 1;
    ts = t->smooth_sum / (double)t->smooth_filled;
/*@ end smoothing */

    /* Backward differences (3x_i - 4x_{i-s} + x_{i-2s}) / (2H) of smoothed T, then of Tdot. */
    t->temp_ring[slot] = ts;
    tdot = t->history < 2 * s
               ? 0.0
               : (3.0 * ts - 4.0 * t->temp_ring[back1] + t->temp_ring[back2]) / DRIFTLAB_TWO_H_S;
    t->tdot_ring[slot] = tdot;
    tddot = t->history < 4 * s
                ? 0.0
                : (3.0 * tdot - 4.0 * t->tdot_ring[back1] + t->tdot_ring[back2]) /
                      DRIFTLAB_TWO_H_S;
    if (t->history < 4 * s) {
        t->history++;
    }
    t->slot = slot + 1 == len ? 0 : slot + 1;
/*@ end temperature_push */
    *tdot_out = tdot;
    *tddot_out = tddot;
}
/*@ end temperature */
