/* One policy for the masses every reader hands out (docs/input.md): a mass
 * is a weight deposited into the image, so it must be a finite number, not
 * negative, and survive the conversion to float (a positive mass that would
 * become 0 or infinite is refused rather than silently dropped). Each reader
 * checks the value as stored in its file and names file, particle and value. */
#ifndef ORR_SOURCE_MASS_POLICY_H
#define ORR_SOURCE_MASS_POLICY_H

/* What is wrong with the mass m ("is negative", ...), or NULL when it is
 * usable. */
const char *orr_mass_problem(double m);

#endif
