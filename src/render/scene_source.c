/* Opens the particle source a scene's render asks for (render/source_request.h),
 * for the plan, the observer frame, the dust and the path overview. Reads
 * the request the plan compiled, not the scene. */
#include "render/source_request.h"

orr_status orr_source_request_open(const orr_source_request *r, const char *const *fields, int nfields,
                                   orr_source **out, orr_error *err)
{
    return orr_source_request_open_share(r, fields, nfields, 0, 1, out, err);
}

orr_status orr_source_request_open_share(const orr_source_request *r, const char *const *fields, int nfields,
                                         int part, int nparts, orr_source **out, orr_error *err)
{
    orr_input_request req = {r->scene_path, r->reader_types, r->model_types, fields, nfields, part, nparts};
    return orr_input_open(r->input, &req, out, err);
}
