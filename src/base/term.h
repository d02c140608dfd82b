/* term.h - text from a file made safe to print on a terminal.
 *
 * A name or string read from a project, rule or terrain file, or from a database, can
 * hold bytes a terminal obeys: a newline starts a forged line, ESC [ 8 m hides what
 * follows, a right-to-left override reorders it.  Everything such text prints goes
 * through rf_term_escape (or rf_term_fputs): C0 controls and DEL as \n, \r, \t or \xHH,
 * bytes that are not UTF-8 as \xHH, and the C1 controls (U+0080..U+009F) and the
 * bidirectional marks, embeddings, overrides and isolates (U+061C, U+200E, U+200F,
 * U+202A..U+202E, U+2066..U+2069) as \uHHHH.  Any other UTF-8 text is kept as it is. */
#ifndef ROCKFALL_TERM_H
#define ROCKFALL_TERM_H

#include <stddef.h>
#include <stdio.h>

/* s escaped into buf (size >= 4 bytes, NUL-terminated); text that does not fit ends
 * in "...".  Returns buf. */
const char *rf_term_escape(const char *s, char *buf, size_t size);
/* s escaped, whatever its length, to out. */
void rf_term_fputs(const char *s, FILE *out);

#endif
