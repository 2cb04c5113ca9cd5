/* The objectives' names (squama/fitness.h), on their own: the batch's done.json reader uses
 * them without the rest of the fitness module (tests/fuzz). */
#include "squama/fitness.h"

const char *sq_fit_objective_name(int i)
{
    static const char *const names[SQ_OBJ_COUNT] = {"palette", "histogram", "shape", "along", "across"};
    return i >= 0 && i < SQ_OBJ_COUNT ? names[i] : "?";
}
