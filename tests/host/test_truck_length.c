/*
 * Trucks of length in the node model against the object model
 * (sim_host/ref/node_model.h, spacing policies).
 *
 *     test_truck_length ROADS_DIR      (or PFE_ROADS_DIR in the environment)
 *
 * Hand-computed: the default platoon (h 0.4 s, d0 0 m, 90 km/h) of 16.5 m
 * trucks under the headway policy has T = (16.5 + 0 + 0.4 x 25) / 25 =
 * 26.5 / 25 = 1.06 s between two fronts passing a point, and the gap
 * T v - L, at least the 3 m floor: 10 m at 25 m/s, 1.06 x 20 - 16.5 = 4.7 m
 * at 20 m/s, 3 m (not -0.6 m) at 15 m/s. Point masses: T = 10 / 25 = 0.4 s,
 * the gap 0.4 v, the same as d0 + h v above 3 / 0.4 = 7.5 m/s.
 *
 * The comparison (issue: object within 0.3 % of node on the three roads and
 * 250 random routes with 16.5 m trucks) is printed in full. The object
 * model with the followers driven by their own controller meets it (the
 * last two tests); the other variants do not, and the asserts hold the
 * figures each reaches, stated in node_model.h, so that a change that
 * moves them is seen.
 */
#include <inttypes.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "ref/node_model.h"
#include "ref/ref_model.h"
#include "lib/route_gen.h"

static const char *g_roads_dir;

#define LENGTH_M 16.5
#define ROUTES 250U

/* |x| <= limit, printing both (x and limit in thousandths). */
#define assert_abs_within(x, limit)                                                                   \
    assert_in_range(lround(1000.0 * fabs(x)), 0, lround(1000.0 * (limit)))

static node_sim_t g_node;

typedef struct {
    double node_l, object_l, trucks_l, drag_l, min_gap_m, min_kmh, follower_brake_mj, follower_fuel_l;
} compare_t;

static void compare(const node_config_t *cfg, const ref_road_t *road, compare_t *c)
{
    static ref_platoon_t pl;
    static object_sim_t o;
    model_summary_t node, object;
    memset(&g_node, 0xA5, sizeof g_node);
    assert_int_equal(node_sim_init(&g_node, cfg, road), 0);
    assert_int_equal(node_sim_run(&g_node, &node), 0);
    c->node_l = node.fuel_l;
    c->min_gap_m = node.min_gap_m;
    c->min_kmh = node.min_kmh;
    c->follower_brake_mj = 0.0;
    c->follower_fuel_l = 0.0;
    for (unsigned i = 1U; i < cfg->n_vehicles; i++) {
        c->follower_brake_mj += g_node.brake_j[i] / 1e6;
        c->follower_fuel_l += g_node.fuel_l[i];
    }
    assert_int_equal(object_platoon_build(&pl, cfg, OBJECT_NOMINAL), 0);
    /* 0: eq. 4.10 and 4.7; 1: the grade under each truck; 2: the policy's gap at the speed */
    for (int variant = 0; variant < 3; variant++) {
        assert_int_equal(object_sim_init(&o, &pl, cfg->cruise, road, cfg->set_speed_m_s,
                                         cfg->initial_speed_m_s, cfg->step_s), 0);
        if (variant == 1) {
            object_sim_truck_grades(&o, cfg->n_vehicles,
                                    cfg->length_m + node_desired_gap_m(cfg, cfg->set_speed_m_s));
        } else if (variant == 2) {
            object_sim_policy_drag(&o, cfg);
        }
        assert_int_equal(object_sim_run(&o, &object), 0);
        double *out[3] = {&c->object_l, &c->trucks_l, &c->drag_l};
        *out[variant] = object.fuel_l;
    }
}

/* A bundled road by name (flat, uphill, hilly) into *road. */
static void load_bundled(const char *name, node_road_t *road)
{
    char path[1024], err[512];
    snprintf(path, sizeof path, "%s/%s.csv", g_roads_dir, name);
    if (node_road_load(path, road, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
}

/* The seeded random hilly route (route_gen.h) into *road. */
static void load_route(uint64_t seed, node_road_t *road)
{
    static int32_t mpct[ROUTE_HILLY_SAMPLES];
    static double grade[ROUTE_HILLY_SAMPLES];
    route_gen_hilly(seed, mpct);
    for (size_t k = 0U; k < ROUTE_HILLY_SAMPLES; k++) {
        grade[k] = mpct[k] / 1000.0;
    }
    assert_int_equal(node_road_from_percent(grade, ROUTE_HILLY_SAMPLES, ROUTE_HILLY_SPACING_M, road), 0);
}

static double pct(double x, double ref)
{
    return 100.0 * (x - ref) / ref;
}

static void test_headway_gap_is_hand_computed(void **state)
{
    (void)state;
    node_config_t cfg;
    node_config_default(&cfg, 5U);
    cfg.length_m = LENGTH_M;
    cfg.spacing = NODE_SPACING_HEADWAY;
    assert_int_equal(node_config_check(&cfg, NULL, 0U), 0);
    assert_in_range(lround(node_headway_s(&cfg) * 1e9), 1059999999, 1060000001);
    assert_in_range(lround(node_desired_gap_m(&cfg, 25.0) * 1e9), 9999999999, 10000000001);
    assert_in_range(lround(node_desired_gap_m(&cfg, 20.0) * 1e9), 4699999999, 4700000001);
    assert_in_range(lround(node_desired_gap_m(&cfg, 15.0) * 1e9), 2999999999, 3000000001);
    cfg.headway_floor_m = 0.0;
    assert_int_equal(lround(node_desired_gap_m(&cfg, 15.0) * 1e9), 0);
    cfg.spacing = NODE_SPACING_GAP;
    assert_in_range(lround(node_desired_gap_m(&cfg, 20.0) * 1e9), 7999999999, 8000000001);
    char err[128];
    cfg.headway_floor_m = -1.0;
    assert_int_equal(node_config_check(&cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "smallest gap"));
    cfg.headway_floor_m = 3.0;
    cfg.spacing = (node_spacing_t)7;
    assert_int_equal(node_config_check(&cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "spacing policy"));
}

/* For point masses the headway policy is the gap policy (above the floor's
 * 27 km/h): every figure of the thesis tables (length 0) is the same, bit
 * for bit. */
static void test_headway_is_the_gap_policy_for_point_masses(void **state)
{
    (void)state;
    node_road_t road;
    load_bundled("hilly", &road);
    node_config_t cfg;
    node_config_default(&cfg, 5U);
    cfg.length_m = 0.0;
    compare_t gap, headway;
    compare(&cfg, &road.road, &gap);
    cfg.spacing = NODE_SPACING_HEADWAY;
    compare(&cfg, &road.road, &headway);
    node_road_free(&road);
    print_message("point masses, hilly: node %.6f L (gap policy) and %.6f L (headway)\n", gap.node_l,
                  headway.node_l);
    assert_memory_equal(&gap.node_l, &headway.node_l, sizeof gap.node_l);
    assert_memory_equal(&gap.min_gap_m, &headway.min_gap_m, sizeof gap.min_gap_m);
}

/* The bundled roads with 16.5 m trucks under both policies. */
static void test_bundled_roads_with_trucks_of_length(void **state)
{
    (void)state;
    static const char *const names[] = {"flat", "uphill", "hilly"};
    /* the figures node_model.h states, each with 0.05 % to spare */
    static const double headway_limit_pct[] = {0.05, 0.81, 1.36};
    for (size_t k = 0U; k < 3U; k++) {
        node_road_t road;
        load_bundled(names[k], &road);
        node_config_t cfg;
        node_config_default(&cfg, 5U);
        compare_t point, gap, headway;
        cfg.length_m = 0.0;
        compare(&cfg, &road.road, &point);
        cfg.length_m = LENGTH_M;
        compare(&cfg, &road.road, &gap);
        cfg.spacing = NODE_SPACING_HEADWAY;
        compare(&cfg, &road.road, &headway);
        node_road_free(&road);
        print_message("%-6s point masses: object %+.3f %% of node; followers brake %.2f MJ\n", names[k],
                      pct(point.object_l, point.node_l), point.follower_brake_mj);
        print_message("%-6s 16.5 m, gap:     object %+.3f %% (grade under each truck %+.3f %%), followers "
                      "burn %+.2f %% against point masses and brake %.2f MJ, smallest gap %.2f m\n",
                      names[k], pct(gap.object_l, gap.node_l), pct(gap.trucks_l, gap.node_l),
                      pct(gap.follower_fuel_l, point.follower_fuel_l), gap.follower_brake_mj, gap.min_gap_m);
        print_message("%-6s 16.5 m, headway: object %+.3f %% (grade under each truck %+.3f %%, the gap's "
                      "drag at each speed %+.3f %%), followers burn %+.2f %% against point masses and "
                      "brake %.2f MJ, smallest gap %.2f m at %.1f km/h lowest\n",
                      names[k], pct(headway.object_l, headway.node_l), pct(headway.trucks_l, headway.node_l),
                      pct(headway.drag_l, headway.node_l),
                      pct(headway.follower_fuel_l, point.follower_fuel_l), headway.follower_brake_mj,
                      headway.min_gap_m, headway.min_kmh);
        assert_abs_within(pct(headway.object_l, headway.node_l), headway_limit_pct[k]);
        /* most of the uphill difference is the gap's drag: with it, within 0.1 % */
        if (k == 1U) {
            assert_abs_within(pct(headway.drag_l, headway.node_l), 0.1);
        }
        /* under the headway policy the followers brake no more than point masses do */
        assert_in_range(lround(1000.0 * headway.follower_brake_mj), 0, lround(1000.0 * point.follower_brake_mj));
        /* the gap stays at or above the drag table's first point (2 m): below it
         * the table is held, and the trucks are close to touching */
        assert_in_range(lround(1000.0 * headway.min_gap_m), 2000, 10000);
    }
}

/* 250 seeded random hilly routes (route_gen.h), 16.5 m trucks. */
static void test_random_routes_with_trucks_of_length(void **state)
{
    (void)state;
    double worst[4] = {0.0, 0.0, 0.0, 0.0}, sum_abs[4] = {0.0, 0.0, 0.0, 0.0}, smallest_gap = INFINITY;
    unsigned within[4] = {0U, 0U, 0U, 0U}, below_2m = 0U, below_2m_no_floor = 0U;
    double smallest_no_floor = INFINITY;
    uint64_t worst_seed[4] = {0U, 0U, 0U, 0U}, gap_seed = 0U;
    for (uint64_t seed = 1U; seed <= ROUTES; seed++) {
        node_road_t r;
        load_route(seed, &r);
        node_config_t cfg;
        node_config_default(&cfg, 5U);
        compare_t c[4];
        cfg.length_m = 0.0;
        compare(&cfg, &r.road, &c[0]);
        cfg.length_m = LENGTH_M;
        compare(&cfg, &r.road, &c[1]);
        cfg.spacing = NODE_SPACING_HEADWAY;
        compare(&cfg, &r.road, &c[2]);
        cfg.headway_floor_m = 0.0;
        compare(&cfg, &r.road, &c[3]);
        node_road_free(&r);
        below_2m_no_floor += (c[3].min_gap_m < 2.0) ? 1U : 0U;
        smallest_no_floor = fmin(smallest_no_floor, c[3].min_gap_m);
        for (int p = 0; p < 4; p++) {
            const double e = (p < 3) ? pct(c[p].object_l, c[p].node_l) : pct(c[2].drag_l, c[2].node_l);
            sum_abs[p] += fabs(e);
            within[p] += (fabs(e) <= 0.3) ? 1U : 0U;
            if (fabs(e) > fabs(worst[p])) {
                worst[p] = e;
                worst_seed[p] = seed;
            }
        }
        below_2m += (c[2].min_gap_m < 2.0) ? 1U : 0U;
        if (c[2].min_gap_m < smallest_gap) {
            smallest_gap = c[2].min_gap_m;
            gap_seed = seed;
        }
    }
    static const char *const what[] = {"point masses", "16.5 m, gap policy", "16.5 m, headway",
                                       "16.5 m, headway, the gap's drag at each speed"};
    for (int p = 0; p < 4; p++) {
        print_message("%u routes, %-18s: object within 0.3 %% of node on %u, mean |difference| %.3f %%, "
                      "worst %+.3f %% (seed %" PRIu64 ")\n",
                      ROUTES, what[p], within[p], sum_abs[p] / ROUTES, worst[p], worst_seed[p]);
    }
    print_message("%u routes, 16.5 m, headway: smallest gap %.2f m (seed %" PRIu64 "), below 2 m on %u\n",
                  ROUTES, smallest_gap, gap_seed, below_2m);
    print_message("%u routes, 16.5 m, headway without the floor: smallest gap %.2f m, below 2 m on %u\n", ROUTES,
                  smallest_no_floor, below_2m_no_floor);
    /* the figures node_model.h states, with a little to spare */
    assert_in_range(lround(1000.0 * sum_abs[2] / ROUTES), 0, 400);
    assert_in_range(below_2m_no_floor, 100U, ROUTES); /* why the floor */
    assert_abs_within(worst[2], 1.2);
    assert_int_equal(below_2m, 0);
    assert_in_range(lround(1000.0 * sum_abs[1] / ROUTES), 1000, 3000); /* the gap policy: far off */
}

/*
 * Each position's fuel with its own clipping (node_model.h,
 * object_sim_position_fuel), 16.5 m trucks under the headway policy:
 *   0  the policy's drag at the platoon's speed (object_sim_policy_drag),
 *      eq. 4.14's one clipped sum;
 *   1  the same, with eq. 4.11's clipping per position at the point;
 *   2  the same, with the followers where the policy puts them
 *      (OBJECT_FUEL_FOLLOWERS), each with its own speed, grade and gap;
 *   3  the followers as 2 with eq. 4.7's drag in the point's dynamics;
 *   4  the followers as 2 within their force limits and speed cap
 *      (OBJECT_FUEL_FOLLOWERS_LIMITED);
 *   5  policy drag, each follower driven by its own controller, the
 *      node model's law with the configured gains, at its own place
 *      (OBJECT_FUEL_FOLLOWERS_CONTROLLED).
 * The target is 0.3 % on the three roads and on at least 245 of
 * the 250 routes (what point masses reach with eq. 4.14); variant 5
 * reaches it, the others do not. The asserts hold what each reaches, with
 * a little to spare, so that a change that moves them is seen, and the
 * target for variant 5.
 */
#define VARIANTS 6
#define CONTROLLED 5

static double node_fuel(const node_config_t *cfg, const ref_road_t *road)
{
    model_summary_t node;
    memset(&g_node, 0xA5, sizeof g_node);
    assert_int_equal(node_sim_init(&g_node, cfg, road), 0);
    assert_int_equal(node_sim_run(&g_node, &node), 0);
    return node.fuel_l;
}

/* The five 16.5 m trucks under the headway policy on *r (freed): each
 * variant's fuel against the node model's, %. */
static void per_position(node_road_t *r, double out_pct[VARIANTS])
{
    static ref_platoon_t pl;
    static object_sim_t o;
    model_summary_t object;
    node_config_t config;
    node_config_default(&config, 5U);
    config.length_m = LENGTH_M;
    config.spacing = NODE_SPACING_HEADWAY;
    const node_config_t *cfg = &config;
    const ref_road_t *road = &r->road;
    const double node_l = node_fuel(cfg, road);
    assert_int_equal(object_platoon_build(&pl, cfg, OBJECT_NOMINAL), 0);
    for (int v = 0; v < VARIANTS; v++) {
        memset(&o, 0xA5, sizeof o);
        assert_int_equal(object_sim_init(&o, &pl, cfg->cruise, road, cfg->set_speed_m_s, cfg->initial_speed_m_s,
                                         cfg->step_s), 0);
        static const object_fuel_t how[VARIANTS] = {OBJECT_FUEL_AGGREGATE, OBJECT_FUEL_POSITIONS,
                                                    OBJECT_FUEL_FOLLOWERS, OBJECT_FUEL_FOLLOWERS,
                                                    OBJECT_FUEL_FOLLOWERS_LIMITED, OBJECT_FUEL_FOLLOWERS_CONTROLLED};
        if (v != 3) {
            object_sim_policy_drag(&o, cfg);
        }
        object_sim_position_fuel(&o, cfg, how[v]);
        assert_int_equal(object_sim_run(&o, &object), 0);
        out_pct[v] = pct(object.fuel_l, node_l);
    }
    node_road_free(r);
}

static const char *const k_variant[VARIANTS] = {"policy drag, one clipped sum", "policy drag, each position clipped",
                                                "policy drag, followers where the policy puts them",
                                                "followers, eq. 4.7 drag in the dynamics",
                                                "policy drag, followers within their limits",
                                                "policy drag, followers by their own controller"};

static void test_per_position_fuel_on_the_bundled_roads(void **state)
{
    (void)state;
    static const char *const names[] = {"flat", "uphill", "hilly"};
    /* measured, each with 0.03 % to spare: [road][variant]; variant 5
     * measured 0.000, +0.014 and +0.011 % */
    static const double limit_pct[3][VARIANTS] = {{0.03, 0.03, 0.03, 0.03, 0.03, 0.03},
                                                  {0.11, 0.11, 0.08, 0.27, 0.05, 0.05},
                                                  {0.74, 0.76, 0.55, 0.49, 0.87, 0.05}};
    for (size_t k = 0U; k < 3U; k++) {
        node_road_t road;
        load_bundled(names[k], &road);
        double e[VARIANTS];
        per_position(&road, e);
        for (int v = 0; v < VARIANTS; v++) {
            print_message("%-6s 16.5 m, headway, %-50s: object %+.3f %% of node\n", names[k], k_variant[v], e[v]);
        }
        for (int v = 0; v < VARIANTS; v++) {
            assert_abs_within(e[v], limit_pct[k][v]);
        }
        assert_abs_within(e[CONTROLLED], 0.3); /* the target */
    }
}

static void test_per_position_fuel_on_random_routes(void **state)
{
    (void)state;
    double worst[VARIANTS] = {0.0}, sum_abs[VARIANTS] = {0.0};
    unsigned within[VARIANTS] = {0U};
    uint64_t worst_seed[VARIANTS] = {0U};
    char missed[256] = "";
    for (uint64_t seed = 1U; seed <= ROUTES; seed++) {
        node_road_t r;
        load_route(seed, &r);
        double e[VARIANTS];
        per_position(&r, e);
        if (fabs(e[CONTROLLED]) > 0.3) {
            const size_t used = strlen(missed);
            snprintf(missed + used, sizeof missed - used, " %" PRIu64 " (%+.3f %%)", seed, e[CONTROLLED]);
        }
        for (int v = 0; v < VARIANTS; v++) {
            sum_abs[v] += fabs(e[v]);
            within[v] += (fabs(e[v]) <= 0.3) ? 1U : 0U;
            if (fabs(e[v]) > fabs(worst[v])) {
                worst[v] = e[v];
                worst_seed[v] = seed;
            }
        }
    }
    for (int v = 0; v < VARIANTS; v++) {
        print_message("%u routes, 16.5 m, headway, %-50s: within 0.3 %% on %u, mean |difference| %.3f %%, "
                      "worst %+.3f %% (seed %" PRIu64 ")\n",
                      ROUTES, k_variant[v], within[v], sum_abs[v] / ROUTES, worst[v], worst_seed[v]);
    }
    print_message("%u routes, 16.5 m, headway, followers by their own controller: outside 0.3 %% on%s\n", ROUTES,
                  missed);
    /* measured: [mean |difference| in thousandths of a percent, worst, routes
     * within 0.3 %]; variant 5 measured 48, +0.521 % (seed 172), 247, and
     * the issue asks 245 */
    static const long mean_limit[VARIANTS] = {420, 420, 340, 370, 200, 60};
    static const double worst_limit[VARIANTS] = {1.80, 1.80, 1.50, 1.58, 0.87, 0.55};
    static const unsigned within_least[VARIANTS] = {115U, 115U, 140U, 129U, 200U, 245U};
    for (int v = 0; v < VARIANTS; v++) {
        assert_in_range(lround(1000.0 * sum_abs[v] / ROUTES), 0, mean_limit[v]);
        assert_abs_within(worst[v], worst_limit[v]);
        assert_in_range(within[v], within_least[v], ROUTES);
    }
}

int main(int argc, char **argv)
{
    g_roads_dir = (argc > 1) ? argv[1] : getenv("PFE_ROADS_DIR");
    if (g_roads_dir == NULL) {
        fprintf(stderr, "usage: %s ROADS_DIR (or set PFE_ROADS_DIR)\n", argv[0]);
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_headway_gap_is_hand_computed),
        cmocka_unit_test(test_headway_is_the_gap_policy_for_point_masses),
        cmocka_unit_test(test_bundled_roads_with_trucks_of_length),
        cmocka_unit_test(test_random_routes_with_trucks_of_length),
        cmocka_unit_test(test_per_position_fuel_on_the_bundled_roads),
        cmocka_unit_test(test_per_position_fuel_on_random_routes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
