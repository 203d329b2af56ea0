/*
 * The few entry points metabezier uses from COCO's C core (vendored in
 * vendor/coco/, BSD-3-Clause). This file is metabezier's own; it includes
 * the COCO amalgamation so that it can read the problem's optimum, which
 * COCO's public header does not expose.
 *
 * Every call validates its arguments first: COCO's coco_error() ends the
 * process, so no call may reach it from user input.
 */
#include "../vendor/coco/coco.c"

/* A bbob problem with the suite it belongs to. */
typedef struct {
  coco_suite_t *suite;
  coco_problem_t *problem;
} mb_bbob_t;

/* Silences COCO's informational output; call before anything else. */
void mb_coco_quiet(void) { coco_set_log_level("error"); }

/* Whether COCO's bbob suite has this dimension (2, 3, 5, 10, 20, 40). */
int mb_bbob_has_dimension(size_t dimension) {
  const size_t dims[] = {2, 3, 5, 10, 20, 40};
  size_t i;
  for (i = 0; i < sizeof(dims) / sizeof(dims[0]); i++)
    if (dims[i] == dimension) return 1;
  return 0;
}

/* COCO's bbob observer writing into outer_folder/result_folder (COCO
 * appends _001, ... when it exists) under the algorithm name `algorithm`. */
coco_observer_t *mb_observer_new(const char *outer_folder, const char *result_folder, const char *algorithm) {
  char options[3 * 1100];
  if (strlen(outer_folder) > 1000 || strlen(result_folder) > 1000 || strlen(algorithm) > 1000) return NULL;
  snprintf(options, sizeof(options), "outer_folder: %s result_folder: %s algorithm_name: %s log_level: error",
           outer_folder, result_folder, algorithm);
  return coco_observer("bbob", options);
}

/* The folder the observer writes into. */
const char *mb_observer_folder(const coco_observer_t *observer) { return coco_observer_get_result_folder(observer); }

/* Frees an observer; every problem it observed must be freed first. */
void mb_observer_free(coco_observer_t *observer) { coco_observer_free(observer); }

/* Function f (1..24) of the bbob suite at `dimension`, instance `instance`
 * (1..), observed by `observer` when it is not NULL; NULL when an argument
 * is out of range. */
mb_bbob_t *mb_bbob_new(size_t function, size_t dimension, size_t instance, coco_observer_t *observer) {
  char instances[64], options[160];
  mb_bbob_t *b;
  if (function < 1 || function > 24 || !mb_bbob_has_dimension(dimension) || instance < 1 ||
      instance > 1000000)
    return NULL;
  b = (mb_bbob_t *)coco_allocate_memory(sizeof(mb_bbob_t));
  snprintf(instances, sizeof(instances), "instances: %lu", (unsigned long)instance);
  snprintf(options, sizeof(options), "dimensions: %lu function_indices: %lu", (unsigned long)dimension,
           (unsigned long)function);
  b->suite = coco_suite("bbob", instances, options);
  b->problem = coco_suite_get_problem_by_function_dimension_instance(b->suite, function, dimension, instance);
  if (b->problem == NULL) {
    coco_suite_free(b->suite);
    coco_free_memory(b);
    return NULL;
  }
  if (observer != NULL) b->problem = coco_problem_add_observer(b->problem, observer);
  return b;
}

/* f at x (dimension values) into *y. */
void mb_bbob_evaluate(mb_bbob_t *b, const double *x, double *y) { coco_evaluate_function(b->problem, x, y); }

/* The optimal value f*. */
double mb_bbob_fopt(const mb_bbob_t *b) { return b->problem->best_value[0]; }

/* The final target precision Δf (1e-8 on bbob). */
double mb_bbob_final_target_delta(const mb_bbob_t *b) { return b->problem->final_target_delta[0]; }

/* Evaluations counted by COCO. */
size_t mb_bbob_evaluations(const mb_bbob_t *b) { return coco_problem_get_evaluations(b->problem); }

/* Whether the final target was hit. */
int mb_bbob_final_target_hit(const mb_bbob_t *b) { return coco_problem_final_target_hit(b->problem); }

/* COCO's problem id, such as bbob_f008_i02_d05 (valid while b lives). */
const char *mb_bbob_id(const mb_bbob_t *b) { return coco_problem_get_id(b->problem); }

/* Bounds of the region of interest (all coordinates share them on bbob). */
double mb_bbob_lower(const mb_bbob_t *b) { return coco_problem_get_smallest_values_of_interest(b->problem)[0]; }
double mb_bbob_upper(const mb_bbob_t *b) { return coco_problem_get_largest_values_of_interest(b->problem)[0]; }

/* Frees the problem (closing its observer's files for it) and its suite. */
void mb_bbob_free(mb_bbob_t *b) {
  if (b == NULL) return;
  coco_problem_free(b->problem);
  coco_suite_free(b->suite);
  coco_free_memory(b);
}
