//! The reference path of a run, gathered from the samples' `x_d`: one line
//! per plan segment, thinned to a bounded number of points, for the 3D
//! panel of a log and for the figures.

use scenarios::Sample;

use crate::msg;

/// At most this many points over all the segments: an hour of a moving
/// reference at 1 kHz would otherwise keep 3.6 million.
pub const MAX_POINTS: usize = 20_000;

/// A segment's points and the latest `x_d` when it was skipped.
type Strip = (usize, Vec<[f64; 3]>, Option<[f64; 3]>);

/// The reference path as it was flown: per plan segment, the desired
/// positions `x_d` of the samples, in order. A point closer than the
/// current spacing to the last one kept is skipped (the spacing starts at
/// 1 mm and doubles, dropping every other point, whenever the path
/// reaches [`MAX_POINTS`]). A segment without a desired position (attitude
/// mode holding no position, motors off: `x_d` reads 0 throughout) draws
/// nothing.
#[derive(Clone, Debug)]
pub struct ReferencePath {
    /// (segment, points, the latest point when it was skipped) in the
    /// order the segments were flown.
    strips: Vec<Strip>,
    spacing: f64,
    count: usize,
    /// The first sample's time, s.
    t0: Option<f64>,
}

impl Default for ReferencePath {
    fn default() -> Self {
        Self {
            strips: Vec::new(),
            spacing: 1e-3,
            count: 0,
            t0: None,
        }
    }
}

impl ReferencePath {
    /// Adds a sample's `x_d`.
    pub fn push(&mut self, s: &Sample) {
        self.t0.get_or_insert(s.t);
        if !s.xd.iter().all(|c| c.is_finite()) {
            return;
        }
        let spacing = self.spacing;
        let new_strip = self.strips.last().is_none_or(|(k, ..)| *k != s.segment);
        if new_strip {
            self.strips.push((s.segment, Vec::new(), None));
        }
        let Some((_, points, tail)) = self.strips.last_mut() else {
            return;
        };
        let far = points.last().is_none_or(|p| {
            let d = (0..3).map(|i| (p[i] - s.xd[i]).powi(2)).sum::<f64>();
            d >= spacing * spacing
        });
        if far {
            points.push(s.xd);
            *tail = None;
            self.count += 1;
        } else {
            *tail = Some(s.xd);
        }
        if self.count >= MAX_POINTS {
            self.thin();
        }
    }

    /// Keeps every other point of each strip (its ends kept) and doubles
    /// the spacing.
    fn thin(&mut self) {
        self.spacing *= 2.0;
        self.count = 0;
        for (_, points, _) in &mut self.strips {
            let last = points.last().copied();
            let mut k = 0;
            points.retain(|_| {
                k += 1;
                k % 2 == 1
            });
            if let Some(p) = last
                && points.last() != Some(&p)
            {
                points.push(p);
            }
            self.count += points.len();
        }
    }

    /// The lines to draw: (segment, points) for each segment with a desired
    /// position and at least two points, each ending at its segment's last
    /// `x_d`.
    pub fn lines(&self) -> Vec<(usize, Vec<[f64; 3]>)> {
        self.strips
            .iter()
            .map(|(k, p, tail)| {
                let mut p = p.clone();
                p.extend(tail.filter(|t| p.last() != Some(t)));
                (*k, p)
            })
            .filter(|(_, p)| p.len() >= 2 && p.iter().any(|x| *x != [0.0; 3]))
            .collect()
    }

    /// The first sample's time, s (`None` before any).
    pub fn start(&self) -> Option<f64> {
        self.t0
    }

    /// The path as one `foxglove.SceneUpdate` with the time of the run's
    /// first sample, s: an entity per segment in frame `ned`, each a line strip (the
    /// 3D panel draws it for the whole run; its lifetime is unlimited).
    pub(crate) fn scene_update(&self) -> Option<(f64, msg::SceneUpdate)> {
        let entities: Vec<_> = self
            .lines()
            .into_iter()
            .map(|(k, points)| {
                let line = msg::LinePrimitive {
                    r#type: msg::line_primitive::Type::LineStrip as i32,
                    pose: None,
                    thickness: 2.0,
                    scale_invariant: true,
                    points: points
                        .iter()
                        .map(|p| msg::Point3 {
                            x: p[0],
                            y: p[1],
                            z: p[2],
                        })
                        .collect(),
                    color: Some(msg::Color {
                        r: 1.0,
                        g: 0.6,
                        b: 0.1,
                        a: 1.0,
                    }),
                    colors: Vec::new(),
                    indices: Vec::new(),
                };
                msg::SceneEntity {
                    frame_id: "ned".into(),
                    id: format!("segment {k}"),
                    lines: vec![line],
                    ..Default::default()
                }
            })
            .collect();
        if entities.is_empty() {
            return None;
        }
        Some((
            self.start()?,
            msg::SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sample of a short run, its time, segment and `x_d` replaced.
    fn sample(t: f64, segment: usize, xd: [f64; 3]) -> Sample {
        static TEMPLATE: std::sync::OnceLock<Sample> = std::sync::OnceLock::new();
        let mut s = TEMPLATE
            .get_or_init(|| {
                let mut scene = scenes::builtin::hover_disturbed();
                scene.duration = 0.01;
                let out = scenes::run(&scene, Default::default()).unwrap();
                out.samples[0].clone()
            })
            .clone();
        (s.t, s.segment, s.xd) = (t, segment, xd);
        s
    }

    #[test]
    fn a_path_is_split_by_segment_and_skips_one_without_a_position() {
        let mut p = ReferencePath::default();
        for k in 0..100 {
            let t = k as f64 * 0.01;
            // Segment 0 holds no position; 1 climbs 1 cm per sample; 2
            // holds still (one point: no line).
            let (seg, xd) = match k {
                0..30 => (0, [0.0; 3]),
                30..60 => (1, [0.0, 0.0, -0.01 * (k - 30) as f64]),
                _ => (2, [1.0, 2.0, 3.0]),
            };
            p.push(&sample(t, seg, xd));
        }
        let lines = p.lines();
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].0, 1);
        assert_eq!(lines[0].1.len(), 30);
        assert_eq!(lines[0].1[29], [0.0, 0.0, -0.29]);
        assert_eq!(p.start(), Some(0.0));
    }

    #[test]
    fn a_long_path_is_thinned_under_the_bound_keeping_its_ends() {
        let mut p = ReferencePath::default();
        let n = 5 * MAX_POINTS;
        let at = |k: usize| {
            let a = k as f64 * 1e-3;
            [a.cos(), a.sin(), 0.0]
        };
        for k in 0..n {
            p.push(&sample(k as f64 * 1e-3, 0, at(k)));
        }
        let lines = p.lines();
        let points = &lines[0].1;
        assert!(points.len() < MAX_POINTS, "{}", points.len());
        assert!(points.len() > MAX_POINTS / 4, "{}", points.len());
        assert_eq!(points[0], at(0));
        assert_eq!(*points.last().unwrap(), at(n - 1));
        // Every kept point lies on the circle the samples traced.
        for q in points {
            assert!((q[0].hypot(q[1]) - 1.0).abs() < 1e-12);
        }
    }
}
