/**
 * File and Directory Entries as a browser hands a dropped folder over (the API the page walks in
 * io/folderDrop.ts), built from names: a folder's reader gives its entries in batches of `batch`,
 * then an empty batch, as Chromium's does for large folders.
 */
import type { EntryLike } from '../../web/src/io/folderDrop';

/** A file entry holding one byte. */
export const fileEntry = (name: string): EntryLike => ({
  isFile: true,
  isDirectory: false,
  name,
  file: (ok) => ok(new File(['x'], name)),
});

/** A folder entry whose reader hands `children` over `batch` at a time. */
export const folderEntry = (name: string, children: EntryLike[], batch = 2): EntryLike => ({
  isFile: false,
  isDirectory: true,
  name,
  createReader: () => {
    let at = 0;
    return {
      readEntries: (ok) => {
        const next = children.slice(at, at + batch);
        at += next.length;
        ok(next);
      },
    };
  },
});
