#include "source/readers/formats.h"

#include "source/readers/gadget.h"
#include "source/readers/hdf5_reader.h"
#include "source/readers/npy_reader.h"
#include "source/readers/npz_reader.h"
#include "source/readers/text_reader.h"
#include "source/readers/tipsy.h"

/* Binary formats first: their probes check magic numbers and record
 * structure, while the text probe accepts any printable table. */
const orr_format orr_formats[] = {
    {"hdf5", orr_hdf5_probe, orr_hdf5_source_open},
    {"gadget", orr_gadget_probe, orr_gadget_source_open},
    {"tipsy", orr_tipsy_probe, orr_tipsy_source_open},
    {"npy", orr_npy_probe, orr_npy_source_open},
    {"npz", orr_npz_probe, orr_npz_source_open},
    {"text", orr_text_probe, orr_text_source_open},
};

const int orr_nformats = (int)(sizeof orr_formats / sizeof orr_formats[0]);
