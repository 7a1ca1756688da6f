/* Named Gadget blocks (gadget_internal.h): which particles a SnapFormat 2
 * block with a label of its own (AGE, Z, NHP, a user's block) has values
 * for. Gadget writes such a block with one or more values per particle of
 * the types it concerns, in type order, and nothing says which types:
 * gas-only blocks (U, NE, SFR) have npart[0] values, AGE often only the
 * stars', Z the gas and stars', BH blocks only type 5's. So the layout is
 * inferred from the block's length in every part of the snapshot. */
#include "source/readers/gadget_internal.h"

#include <stdio.h>
#include <string.h>

const gadget_named_block *gadget_named_find(const gadget_file *f, const char *label)
{
    for (int i = 0; i < f->nnamed; i++)
        if (strcmp(f->named[i].label, label) == 0)
            return &f->named[i];
    return NULL;
}

static int64_t count_of(const gadget_file *f, unsigned types)
{
    int64_t n = 0;
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (types >> t & 1u)
            n += f->h.npart[t];
    return n;
}

/* The values per particle when the types `types` fit the block in every
 * part, else 0. */
static int fits(const gadget_file *files, int nfiles, const char *label, unsigned types, int elem)
{
    int ncomp = 0;
    for (int i = 0; i < nfiles; i++) {
        const gadget_named_block *b = gadget_named_find(&files[i], label);
        int64_t n = count_of(&files[i], types);
        if (n == 0) {
            if (b && b->bytes != 0)
                return 0; /* values, but none of these particles here */
            continue;
        }
        if (!b || b->bytes % (n * elem) != 0)
            return 0;
        int64_t k = b->bytes / (n * elem);
        if (k < 1 || k > GADGET_NAMED_MAX_COMPONENTS || (ncomp && k != ncomp))
            return 0;
        ncomp = (int)k;
    }
    return ncomp;
}

void gadget_type_list(unsigned types, char *buf, size_t size)
{
    int n = 0;
    for (int t = 0; t < GADGET_NTYPES; t++)
        n += (int)(types >> t & 1u);
    size_t used = (size_t)snprintf(buf, size, "%s", n == 1 ? "type" : "types");
    for (int t = 0; t < GADGET_NTYPES && used + 3 < size; t++)
        if (types >> t & 1u)
            used += (size_t)snprintf(buf + used, size - used, " %d", t);
}

/* The conventional type sets, among the snapshot's non-empty types
 * `present`, most likely first; duplicates and empty sets left out. */
static int conventional_sets(const gadget_file *f0, unsigned present, unsigned sets[6])
{
    unsigned massless = 0;
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (f0->h.massarr[t] == 0)
            massless |= 1u << t;
    const unsigned all[6] = {present, 1u << 0, 1u << 4, (1u << 0) | (1u << 4), 1u << 5, massless};
    int n = 0;
    for (int i = 0; i < 6; i++) {
        unsigned s = all[i] & present;
        int seen = !s;
        for (int j = 0; j < n; j++)
            seen |= sets[j] == s;
        if (!seen)
            sets[n++] = s;
    }
    return n;
}

/* How many of `n` candidate sets fit; the first one that does in *first,
 * each one described in list. */
static int count_fits(const gadget_file *files, int nfiles, const char *label, const unsigned *sets, int n, int elem,
                      unsigned *first, int *first_ncomp, char *list, size_t size)
{
    const char *precision = elem == 8 ? "double" : "float";
    int found = 0;
    for (int i = 0; i < n; i++) {
        int k = fits(files, nfiles, label, sets[i], elem);
        if (!k)
            continue;
        if (!found) {
            *first = sets[i];
            *first_ncomp = k;
        }
        char types[24];
        gadget_type_list(sets[i], types, sizeof types);
        size_t used = strlen(list);
        snprintf(list + used, size - used, "%s%d %s%s per particle of %s", found ? ", or " : "", k, precision,
                 k == 1 ? "" : "s", types);
        found++;
    }
    return found;
}

void gadget_named_infer(const gadget_file *files, int nfiles, const char *label, gadget_named_layout *out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->label, sizeof out->label, "%s", label);
    unsigned present = 0;
    for (int i = 0; i < nfiles; i++)
        for (int t = 0; t < GADGET_NTYPES; t++)
            if (files[i].h.npart[t] > 0)
                present |= 1u << t;
    out->elem = files[0].blk[BLK_POS].elem == 8 ? 8 : 4;
    unsigned sets[64];
    int nsets = conventional_sets(&files[0], present, sets);
    char list[sizeof out->why - 48] = "";
    int found = count_fits(files, nfiles, label, sets, nsets, out->elem, &out->types, &out->ncomp, list, sizeof list);
    if (!found) { /* any other set of the types there are */
        int n = 0;
        for (unsigned s = 1; s < 64; s++) {
            int conventional = 0;
            for (int j = 0; j < nsets; j++)
                conventional |= sets[j] == s;
            if ((s & present) == s && !conventional)
                sets[n++] = s;
        }
        found = count_fits(files, nfiles, label, sets, n, out->elem, &out->types, &out->ncomp, list, sizeof list);
    }
    if (found == 1) {
        out->ok = 1;
        return;
    }
    if (found > 1) {
        snprintf(out->why, sizeof out->why, "cannot tell which particles it covers: %s", list);
        return;
    }
    const gadget_named_block *b = NULL;
    int part = 0;
    for (; part < nfiles && !b; part++)
        b = gadget_named_find(&files[part], label);
    const int32_t *np = files[part - 1].h.npart;
    snprintf(out->why, sizeof out->why,
             "%lld bytes (part %d, npart %d %d %d %d %d %d) are no whole number of %ss per particle of any set of "
             "the snapshot's types in every part",
             b ? (long long)b->bytes : 0LL, part - 1, np[0], np[1], np[2], np[3], np[4], np[5],
             out->elem == 8 ? "double" : "float");
}

int64_t gadget_named_row(const gadget_named_layout *l, const gadget_file *f, int t, int64_t within)
{
    int64_t before = 0;
    for (int u = 0; u < t; u++)
        if (l->types >> u & 1u)
            before += f->h.npart[u];
    return before + within;
}
