//! Which frame of one cine stack shows the heart in the phase a frame of another shows.
//!
//! A study's stacks are separate breath-holds: a long-axis cine may hold 25 frames where the
//! short-axis one holds 30, and Segment keeps each stack's own end-diastole (`EDT`) and
//! end-systole (`EST`), which need not fall on the same frame number (a cine's frames shifted in
//! Segment move its `EDT`). Reading frame 10 of every stack would then mix phases; each frame of
//! the main stack is instead matched to the other stack's frame at the same point of the cycle,
//! the two stacks' ED and ES frames matched exactly and the frames between them spread evenly
//! (retrospectively gated cines cover one heartbeat each, whatever its length in ms, so the
//! fraction of the cycle, not the time since the R wave, is what two stacks share).

/// One stack's frames and the phases it names, frames from 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    pub frames: usize,
    pub end_diastole: Option<usize>,
    pub end_systole: Option<usize>,
}

impl Cycle {
    /// The stack's end-diastole and end-systole where both are frames of it and differ (Segment
    /// leaves both at 1 until the phases are set).
    fn anchors(&self) -> (Option<usize>, Option<usize>) {
        let within = |f: Option<usize>| f.filter(|&f| f < self.frames);
        let ed = within(self.end_diastole);
        let es = within(self.end_systole).filter(|&es| Some(es) != ed);
        (ed, es)
    }
}

/// For each frame of `main`, the frame of `stack` at the same point of the cycle; None where
/// that is frame for frame (same count, same phases) or `stack` is a single frame (a still
/// image, read where it was taken, never repeated into every phase).
pub fn match_frames(main: Cycle, stack: Cycle) -> Option<Vec<usize>> {
    let (tm, td) = (main.frames, stack.frames);
    if td <= 1 || tm == 0 {
        return None;
    }
    let (main_ed, main_es) = main.anchors();
    let (stack_ed, stack_es) = stack.anchors();
    // Frames from the shared end-diastole (frame 0 of both when either lacks one), around the cycle.
    let (from_m, from_d) = match (main_ed, stack_ed) {
        (Some(m), Some(d)) => (m, d),
        _ => (0, 0),
    };
    let systole = match (main_ed, main_es, stack_ed, stack_es) {
        (Some(_), Some(m), Some(_), Some(d)) => {
            Some(((m + tm - from_m) % tm, (d + td - from_d) % td))
        }
        _ => None,
    };
    let spread = |off: usize, span_m: usize, span_d: usize| -> usize {
        // Even spacing of `span_m` main frames over `span_d` stack frames, halves rounded up.
        (off as f64 * span_d as f64 / span_m as f64).round() as usize
    };
    let frames: Vec<usize> = (0..tm)
        .map(|k| {
            let off = (k + tm - from_m) % tm;
            let into = match systole {
                Some((sm, sd)) if off < sm => spread(off, sm, sd),
                Some((sm, sd)) => sd + spread(off - sm, tm - sm, td - sd),
                None => spread(off, tm, td),
            };
            (from_d + into) % td
        })
        .collect();
    let frame_for_frame = frames.iter().enumerate().all(|(k, &f)| k == f) && tm == td;
    (!frame_for_frame).then_some(frames)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cycle(frames: usize, ed: usize, es: usize) -> Cycle {
        Cycle {
            frames,
            end_diastole: Some(ed),
            end_systole: Some(es),
        }
    }

    #[test]
    fn frame_for_frame_and_stills_need_no_matching() {
        assert_eq!(match_frames(cycle(20, 0, 9), cycle(20, 0, 9)), None);
        assert_eq!(match_frames(cycle(20, 0, 9), cycle(1, 0, 0)), None);
        // A stack whose phases are unset (both 1) against a main stack at ED 1.
        assert_eq!(match_frames(cycle(20, 0, 9), cycle(20, 0, 0)), None);
        let none = Cycle {
            frames: 20,
            end_diastole: None,
            end_systole: None,
        };
        assert_eq!(match_frames(none, cycle(20, 0, 0)), None);
    }

    #[test]
    fn end_diastole_and_end_systole_meet_and_the_rest_spread_evenly() {
        // 30 short-axis frames (ED 1, ES 11) against a 25-frame view (ED 3, ES 11).
        let map = match_frames(cycle(30, 0, 10), cycle(25, 2, 10)).unwrap();
        assert_eq!(map.len(), 30);
        assert_eq!((map[0], map[10]), (2, 10));
        // Systole: 10 main frames over 8; diastole: 20 over 17, wrapping past the last frame.
        assert_eq!(map[5], 6);
        assert_eq!(map[29], 1);
        // Around the cycle from ED, each step moves 0 to 2 frames forward.
        for k in 0..30 {
            let step = (map[(k + 1) % 30] + 25 - map[k]) % 25;
            assert!(step <= 2, "{k}: {map:?}");
        }
        // Every frame of the view in use but for the few a coarser main stack skips.
        let mut used = map.clone();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used.len(), 25);
    }

    #[test]
    fn without_both_phases_the_cycle_is_shared_in_proportion() {
        let ed_only = Cycle {
            frames: 25,
            end_diastole: Some(4),
            end_systole: None,
        };
        let map = match_frames(cycle(20, 0, 8), ed_only).unwrap();
        // Frame 10 of 20 is 12.5 of 25 frames on, rounded up; frame 19, 23.75 on, wraps to 3.
        assert_eq!((map[0], map[10], map[19]), (4, 17, 3));
        // Same count, ED shifted: a shift.
        let shifted = match_frames(cycle(20, 0, 8), cycle(20, 3, 11)).unwrap();
        assert_eq!(shifted, (0..20).map(|k| (k + 3) % 20).collect::<Vec<_>>());
        // Phases out of range count as unset.
        let wild = match_frames(cycle(10, 0, 4), cycle(5, 40, 70)).unwrap();
        assert_eq!(wild, [0, 1, 1, 2, 2, 3, 3, 4, 4, 0]);
    }
}
