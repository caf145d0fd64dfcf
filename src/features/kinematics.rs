//! Kinematic quantities of a point's trajectory — speed, acceleration, jerk, curvature, distance
//! from the origin — by central differences, shared by the methods that read motion as signals
//! (the hand-speed baseline, the LMA feature pool and Effort descriptors).

use glam::DVec3;

/// Per-frame kinematic quantities of one joint's trajectory (positions relative to the torso).
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    pub speed: Vec<f64>,
    pub acceleration: Vec<f64>,
    pub jerk: Vec<f64>,
    /// `|v × a| / |v|³` (0 where the joint does not move).
    pub curvature: Vec<f64>,
    /// Distance from the torso (the origin of the positions).
    pub distance: Vec<f64>,
}

/// Central differences of `x` at rate `fps` (one-sided at the ends; zeros for fewer than 2 frames).
pub fn derivative(x: &[DVec3], fps: f64) -> Vec<DVec3> {
    let n = x.len();
    (0..n)
        .map(|i| {
            let (a, b, step) = match (i.checked_sub(1), (i + 1 < n).then_some(i + 1)) {
                (Some(a), Some(b)) => (a, b, 2.0),
                (None, Some(b)) => (i, b, 1.0),
                (Some(a), None) => (a, i, 1.0),
                (None, None) => return DVec3::ZERO,
            };
            (x[b] - x[a]) * fps / step
        })
        .collect()
}

impl Kinematics {
    /// The quantities of `positions` (one per frame) sampled at `fps`.
    pub fn of(positions: &[DVec3], fps: f64) -> Kinematics {
        let v = derivative(positions, fps);
        let a = derivative(&v, fps);
        let j = derivative(&a, fps);
        let curvature = v
            .iter()
            .zip(&a)
            .map(|(v, a)| {
                let speed = v.length();
                if speed > 1e-9 {
                    v.cross(*a).length() / speed.powi(3)
                } else {
                    0.0
                }
            })
            .collect();
        Kinematics {
            speed: v.iter().map(|x| x.length()).collect(),
            acceleration: a.iter().map(|x| x.length()).collect(),
            jerk: j.iter().map(|x| x.length()).collect(),
            curvature,
            distance: positions.iter().map(|p| p.length()).collect(),
        }
    }

    /// The speed alone (what the hand-speed segmentation needs).
    pub fn speed(positions: &[DVec3], fps: f64) -> Vec<f64> {
        derivative(positions, fps).iter().map(|v| v.length()).collect()
    }
}

/// The point in columns `col..col + 3` of `features` in every frame.
pub fn points(features: &super::FeatureMatrix, col: usize) -> Vec<DVec3> {
    (0..features.frames())
        .map(|i| {
            let r = &features.row(i)[col..col + 3];
            DVec3::new(r[0] as f64, r[1] as f64, r[2] as f64)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const FPS: f64 = 30.0;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn constant_speed_on_a_line() {
        let p: Vec<DVec3> = (0..40).map(|i| DVec3::new(3.0 * i as f64 / FPS, 1.0, 0.0)).collect();
        let k = Kinematics::of(&p, FPS);
        assert!(k.speed.iter().all(|&v| close(v, 3.0, 1e-9)), "{:?}", k.speed);
        assert!(k.acceleration.iter().all(|&v| v.abs() < 1e-9));
        assert!(k.curvature.iter().all(|&v| v.abs() < 1e-9));
        assert!(close(k.distance[0], 1.0, 1e-12));
    }

    #[test]
    fn uniform_acceleration() {
        // x = ½·2·t²: speed 2t, acceleration 2, jerk 0 (inner frames, where central differences are exact)
        let p: Vec<DVec3> = (0..40).map(|i| DVec3::new(0.0, (i as f64 / FPS).powi(2), 0.0)).collect();
        let k = Kinematics::of(&p, FPS);
        for t in 3..37 {
            assert!(close(k.speed[t], 2.0 * t as f64 / FPS, 1e-9), "speed at {t}");
            assert!(close(k.acceleration[t], 2.0, 1e-9), "acceleration at {t}: {}", k.acceleration[t]);
            assert!(k.jerk[t].abs() < 1e-6, "jerk at {t}: {}", k.jerk[t]);
        }
    }

    #[test]
    fn a_circle_has_curvature_one_over_its_radius() {
        let (r, omega) = (0.5, 2.0);
        let p: Vec<DVec3> = (0..200)
            .map(|i| i as f64 / 120.0)
            .map(|t| DVec3::new(r * (omega * t).cos(), r * (omega * t).sin(), 0.0))
            .collect();
        let k = Kinematics::of(&p, 120.0);
        for t in 5..195 {
            assert!(close(k.speed[t], r * omega, 1e-4), "speed {}", k.speed[t]);
            assert!(close(k.acceleration[t], r * omega * omega, 1e-3), "acceleration {}", k.acceleration[t]);
            assert!(close(k.curvature[t], 1.0 / r, 1e-3), "curvature {}", k.curvature[t]);
        }
    }
}
