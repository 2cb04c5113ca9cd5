/* The search module's random numbers: xoshiro256** seeded by splitmix64. Every optimizer
 * and operator owns one of these; nothing global, so runs are reproducible per seed. */
#ifndef SQ_SEARCH_RNG_H
#define SQ_SEARCH_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct SqRng {
    uint64_t s[4];
    double spare;
    int has_spare;
} SqRng;

static inline uint64_t sq__splitmix(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static inline void sq__rng_seed(SqRng *r, uint64_t seed)
{
    for (int i = 0; i < 4; i++)
        r->s[i] = sq__splitmix(&seed);
    r->has_spare = 0;
    r->spare = 0;
}

static inline uint64_t sq__rng_next(SqRng *r)
{
    uint64_t *s = r->s;
    uint64_t x = s[1] * 5, result = ((x << 7) | (x >> 57)) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = (s[3] << 45) | (s[3] >> 19);
    return result;
}

/* uniform in [0, 1) */
static inline double sq__rng_uniform(SqRng *r)
{
    return (double)(sq__rng_next(r) >> 11) * 0x1.0p-53;
}

/* uniform in [a, b) */
static inline double sq__rng_between(SqRng *r, double a, double b)
{
    return a + (b - a) * sq__rng_uniform(r);
}

/* uniform integer in [0, n) */
static inline int sq__rng_int(SqRng *r, int n)
{
    return n <= 1 ? 0 : (int)(sq__rng_uniform(r) * n);
}

/* standard normal (Marsaglia's polar method) */
static inline double sq__rng_normal(SqRng *r)
{
    if (r->has_spare) {
        r->has_spare = 0;
        return r->spare;
    }
    double u, v, s;
    do {
        u = 2 * sq__rng_uniform(r) - 1;
        v = 2 * sq__rng_uniform(r) - 1;
        s = u * u + v * v;
    } while (s >= 1 || s == 0);
    double k = sqrt(-2 * log(s) / s);
    r->spare = v * k;
    r->has_spare = 1;
    return u * k;
}

#endif
