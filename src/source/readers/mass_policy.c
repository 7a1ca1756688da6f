#include "source/readers/mass_policy.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

const char *orr_mass_problem(double m)
{
    if (!isfinite(m))
        return "is not a finite number";
    if (m < 0)
        return "is negative";
    /* Checked before the conversion: a double beyond FLT_MAX has no float. */
    if (m > FLT_MAX)
        return "is too large for a float (at most 3.4e38): rescale the masses";
    if (m > 0 && (float)m == 0.0f)
        return "is too small for a float (it would become 0; the smallest is 1.4e-45): rescale the masses";
    return NULL;
}
