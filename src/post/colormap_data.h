/* Private to colormap.c: the tabulated colour maps (see colormap_data.c). */
#ifndef ORR_POST_COLORMAP_DATA_H
#define ORR_POST_COLORMAP_DATA_H

#define ORR_CMAP_ENTRIES 256

extern const float orr_cmap_magma[ORR_CMAP_ENTRIES][3];
extern const float orr_cmap_inferno[ORR_CMAP_ENTRIES][3];

#endif
