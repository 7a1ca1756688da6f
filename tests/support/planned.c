#include "planned.h"

#include <stdio.h>
#include <stdlib.h>

orr_projection test_projection_planned(orr_projection_settings settings)
{
    orr_projection p;
    orr_error err = {0};
    if (orr_projection_check(&settings, &err) || orr_projection_plan(&p, &settings, &err)) {
        fprintf(stderr, "test projection refused: %s\n", err.msg);
        exit(1);
    }
    return p;
}
