import { filesOfEntries, folderEntries } from './folderDrop';

/**
 * Drag and drop anywhere on the page. A full-window overlay appears while files are dragged over;
 * the dropped files (and those of dropped folders) are handed over in one batch. `wantsImages`:
 * whether the app waits for the DICOM images of a cvi42 workspace (a dropped folder's files are
 * then all handed over, whatever their names: see io/folderDrop.ts).
 */
export function installDropZone(
  target: HTMLElement,
  overlay: HTMLElement,
  onFiles: (files: File[], skipped: number) => void,
  wantsImages: () => boolean = () => false,
): () => void {
  let depth = 0;
  const hasFiles = (e: DragEvent) => !!e.dataTransfer && Array.from(e.dataTransfer.types).includes('Files');
  const enter = (e: DragEvent) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth++;
    overlay.hidden = false;
  };
  const over = (e: DragEvent) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    if (e.dataTransfer) e.dataTransfer.dropEffect = 'copy';
  };
  const leave = (e: DragEvent) => {
    if (!hasFiles(e)) return;
    depth = Math.max(0, depth - 1);
    if (depth === 0) overlay.hidden = true;
  };
  const drop = (e: DragEvent) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth = 0;
    overlay.hidden = true;
    // A folder (a biv-me patient's) is walked for its files; plain files are handed over as they are.
    const entries = folderEntries(e.dataTransfer);
    if (entries) {
      void filesOfEntries(entries, undefined, wantsImages()).then(({ files, skipped }) => {
        if (files.length) onFiles(files, skipped);
      });
      return;
    }
    const files = Array.from(e.dataTransfer?.files ?? []);
    if (files.length) onFiles(files, 0);
  };
  target.addEventListener('dragenter', enter);
  target.addEventListener('dragover', over);
  target.addEventListener('dragleave', leave);
  target.addEventListener('drop', drop);
  return () => {
    target.removeEventListener('dragenter', enter);
    target.removeEventListener('dragover', over);
    target.removeEventListener('dragleave', leave);
    target.removeEventListener('drop', drop);
  };
}
