/* NSGA-II ranking and crowding on fronts known by construction. */
#include <math.h>

#include "sq_test.h"
#include "squama/search.h"

static void dominance(void **state)
{
    (void)state;
    double a[2] = {1, 2}, b[2] = {2, 2}, c[2] = {1, 2}, d[2] = {0, 3};
    assert_true(sq_pareto_dominates(a, b, 2));
    assert_false(sq_pareto_dominates(b, a, 2));
    assert_false(sq_pareto_dominates(a, c, 2)); /* equal: neither */
    assert_false(sq_pareto_dominates(a, d, 2)); /* trade-off: neither */
    assert_false(sq_pareto_dominates(d, a, 2));
}

static void known_fronts(void **state)
{
    (void)state;
    /* three staircases, shuffled, plus a duplicate */
    const double obj[][2] = {
        {4, 2}, {1, 5}, {5, 5}, {3, 1}, {2, 5}, {2, 3}, {3, 4}, {2, 3}, {6, 6},
    };
    const int want[] = {1, 0, 2, 0, 1, 0, 1, 0, 3};
    int rank[9];
    assert_int_equal(sq_nsga2_rank(&obj[0][0], 9, 2, rank), 4);
    assert_memory_equal(rank, want, sizeof want);
}

static void many_objectives_and_one_point(void **state)
{
    (void)state;
    const double obj[][3] = {{1, 1, 1}, {0, 2, 2}, {2, 0, 2}, {2, 2, 0}, {2, 2, 2}};
    int rank[5];
    assert_int_equal(sq_nsga2_rank(&obj[0][0], 5, 3, rank), 2);
    for (int i = 0; i < 4; i++)
        assert_int_equal(rank[i], 0);
    assert_int_equal(rank[4], 1);
    assert_int_equal(sq_nsga2_rank(&obj[0][0], 1, 3, rank), 1);
    assert_int_equal(rank[0], 0);
    assert_int_equal(sq_nsga2_rank(&obj[0][0], 0, 3, rank), 0);
}

static void crowding_distance(void **state)
{
    (void)state;
    /* one front on a line: x + y = 4 */
    const double obj[][2] = {{0, 4}, {1, 3}, {3, 1}, {4, 0}, {2, 2}};
    int rank[5] = {0, 0, 0, 0, 0};
    double crowd[5];
    sq_nsga2_crowding(&obj[0][0], 5, 2, rank, crowd);
    assert_true(isinf(crowd[0]) && isinf(crowd[3]));
    /* point (1,3): neighbours (0,4) and (2,2): (2-0)/4 in x plus (4-2)/4 in y */
    assert_true(fabs(crowd[1] - 1.0) < 1e-12);
    assert_true(fabs(crowd[4] - 1.0) < 1e-12); /* (2,2): neighbours (1,3), (3,1) */
    assert_true(fabs(crowd[2] - 1.0) < 1e-12);
    /* fronts are measured apart */
    const double two[][2] = {{0, 1}, {1, 0}, {5, 6}, {5.5, 5.5}, {6, 5}};
    int r2[5] = {0, 0, 1, 1, 1};
    double c2[5];
    sq_nsga2_crowding(&two[0][0], 5, 2, r2, c2);
    assert_true(isinf(c2[0]) && isinf(c2[1]) && isinf(c2[2]) && isinf(c2[4]));
    assert_true(fabs(c2[3] - 2.0) < 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dominance),
        cmocka_unit_test(known_fronts),
        cmocka_unit_test(many_objectives_and_one_point),
        cmocka_unit_test(crowding_distance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
