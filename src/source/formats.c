#include "source/formats.h"

#include "source/text_reader.h"

const orr_format orr_formats[] = {
    {"text", orr_text_probe, orr_text_source_open},
};

const int orr_nformats = (int)(sizeof orr_formats / sizeof orr_formats[0]);
