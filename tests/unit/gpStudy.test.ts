// biv-me folders in the app (io/gpStudy.ts): each GPFile is sent to the core with its folder's
// SliceInfoFile, told by content as the core tells them (gpfile::looks_like_gpfile,
// io::looks_like_slice_info). The heads below are the first lines of the biv-me files in
// ../shared/data/contours.
import { describe, expect, it } from 'vitest';
import { isGpFileText, isSliceInfoText, pairSliceInfo, sliceInfoReadText } from '../../web/src/io/gpStudy';

const P1_GP = 'x\ty\tz\tcontour type\tframeID\tweight\ttime frame\n-42.09469\t-25.37305\t-29.46908\tSAX_RV_FREEWALL\t2\t1.0\t0\n';
// Patient 2's end-systolic GPFile has no header row.
const P2_GP_ES = '61.149\t-22.869\t5.669\tLAX_LV_ENDOCARDIAL\t7\t1.0\t12\n61.336\t-23.036\t5.323\tLAX_LV_ENDOCARDIAL\t7\t1.0\t12\n';
const P2_INFO = '1.3.12.2.1107.5.2.41.169616.2019050713353628965132424\tframeID:\t1\tImagePositionPatient\t101.727\t-146.721\t166.633\tImageOrientationPatient\t0.398\t0.856056\t-0.330\t-0.638\t0.000\t-0.770\tPixelSpacing\t1.406\t1.406\n';

const file = (path: string, text: string) => {
  const name = path.split('/').pop() ?? path;
  return Object.assign(new File([text], name), { path });
};
const folderOf = (f: File) => (f as File & { path: string }).path.split('/').slice(0, -1).join('/');

describe('biv-me folders', () => {
  it('tells a GPFile and a SliceInfoFile by their first lines, as the core does', () => {
    expect(isGpFileText(P1_GP)).toBe(true);
    expect(isGpFileText(P2_GP_ES)).toBe(true);
    expect(isGpFileText('\uFEFF1,2,3,RV_INSERT,1\n')).toBe(true);
    expect(isGpFileText('1 2 3 MITRAL_VALVE_PHANTOM 1\n')).toBe(true);
    expect(isGpFileText('contour,x,y,z\ns1,1,2,3\n')).toBe(false);
    expect(isGpFileText('1\t2\t3\tLV_ENDO\n')).toBe(false);
    expect(isGpFileText('1\tx\t3\tSAX_LV_ENDOCARDIAL\n')).toBe(false);
    expect(isGpFileText('')).toBe(false);
    expect(isSliceInfoText(P2_INFO)).toBe(true);
    expect(isSliceInfoText(P1_GP)).toBe(false);
  });

  it('pairs each GPFile with the one SliceInfoFile of its folder; the rest stay as given', async () => {
    const p1 = [file('p1/GPFile_000.txt', P1_GP), file('p1/GPFile_009.txt', P1_GP), file('p1/SliceInfoFile.txt', P2_INFO), file('p1/patient1-ED.csv', 'contour,x,y,z\n')];
    const p2 = [file('p2/GPFile_012.txt', P2_GP_ES), file('p2/SliceInfoFile.txt', P2_INFO)];
    // A folder with a SliceInfoFile and no GPFile, and one with two SliceInfoFiles: left as they are.
    const lone = [file('p3/SliceInfoFile.txt', P2_INFO), file('p3/contours.csv', 'contour,x,y,z\n')];
    const two = [file('p4/GPFile_000.txt', P1_GP), file('p4/SliceInfoFile.txt', P2_INFO), file('p4/SliceInfo_copy.txt', P2_INFO)];
    const { files, sliceInfo } = await pairSliceInfo([...p1, ...p2, ...lone, ...two], folderOf);
    expect(files.map((f) => (f as File & { path: string }).path)).toEqual([
      'p1/GPFile_000.txt', 'p1/GPFile_009.txt', 'p1/patient1-ED.csv', 'p2/GPFile_012.txt',
      'p3/SliceInfoFile.txt', 'p3/contours.csv', 'p4/GPFile_000.txt', 'p4/SliceInfoFile.txt', 'p4/SliceInfo_copy.txt',
    ]);
    expect(sliceInfo.size).toBe(3);
    expect(sliceInfo.get(p1[0])).toBe(p1[2]);
    expect(sliceInfo.get(p1[1])).toBe(p1[2]);
    expect(sliceInfo.get(p2[0])).toBe(p2[1]);
    expect(sliceInfo.has(two[0])).toBe(false);
  });

  it('says which GPFiles were read with which SliceInfoFile', () => {
    expect(sliceInfoReadText([])).toBe('');
    expect(sliceInfoReadText([{ gp: 'GPFile_000.txt', info: 'SliceInfoFile.txt' }])).toBe('SliceInfoFile.txt read with GPFile_000.txt: each contour checked against its image plane.');
    const four = ['a', 'b', 'c', 'd'].map((g, k) => ({ gp: `${g}.txt`, info: k < 2 ? 'SliceInfoFile.txt' : 'S2.txt' }));
    expect(sliceInfoReadText(four)).toBe('2 SliceInfoFiles read with a.txt, b.txt, c.txt and 1 more: each contour checked against its image plane.');
  });
});
