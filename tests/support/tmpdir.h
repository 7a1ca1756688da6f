/* A scratch folder for a test program's files: made once, emptied and
 * removed at the end, and counted (a failed write must leave nothing). */
#ifndef ORR_TEST_TMPDIR_H
#define ORR_TEST_TMPDIR_H

extern char tmpdir[256];

/* Makes /tmp/orr_test_XXXXXX into tmpdir; exits on failure. */
void make_tmpdir(void);
/* Removes everything in it, then the folder. */
void remove_tmpdir(void);
/* Entries in it, . and .. aside. */
int count_entries(void);

#endif
