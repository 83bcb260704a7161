/**
 * One CSV field as RFC 4180 quotes it: ids come from the user's files and may hold a comma or a
 * quote, which would otherwise shift every column after them. Shared by the CSV writers so that
 * they quote alike.
 */
export function csvField(s: string): string {
  return /[",\n\r]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}
