//! Camera math for the skeleton player: an orbit camera around the motion, a perspective
//! projection to canvas pixels (with near-plane clipping of segments), and the floor grid.
//!
//! Pure functions on glam types — no DOM. Positions stay in the file's own coordinates; a
//! [`Basis`] says which axis is up (Y-up or Z-up files), so nothing is converted before drawing.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Vertical field of view of the player camera.
pub const FOV_Y: f32 = 0.75; // radians, ≈ 43°

/// Lowest and highest camera elevation: never exactly overhead or below the floor by much.
const PITCH_RANGE: (f32, f32) = (-0.2, 1.5);

/// Closest and farthest camera distance, as multiples of the motion's bounding radius.
const DISTANCE_RANGE: (f32, f32) = (0.05, 40.0);

/// The world's axes as the file uses them: `up` is vertical; `right` and `back` span the floor.
/// `back` points from the figure toward a viewer standing in front of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis {
    pub up: Vec3,
    pub right: Vec3,
    pub back: Vec3,
}

impl Basis {
    /// Y up, X right, +Z toward the viewer (BVH default, CMU).
    pub const Y_UP: Basis = Basis { up: Vec3::Y, right: Vec3::X, back: Vec3::Z };
    /// Z up, X right, −Y toward the viewer (the Y-up basis turned +90° about X).
    pub const Z_UP: Basis = Basis { up: Vec3::Z, right: Vec3::X, back: Vec3::NEG_Y };

    /// Height of a point above the origin, along `up`.
    pub fn height(&self, p: Vec3) -> f32 {
        p.dot(self.up)
    }

    /// The point dropped straight down (along `up`) onto the floor at height `floor`.
    pub fn on_floor(&self, p: Vec3, floor: f32) -> Vec3 {
        p - self.up * (self.height(p) - floor)
    }
}

/// An orbit camera: it looks at `target` from `distance` away, turned `yaw` radians about the
/// up axis (0 = in front, on `back`) and raised `pitch` radians above the floor plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    /// Radius of the motion's bounding sphere; scales clipping planes and zoom limits.
    pub radius: f32,
}

impl Orbit {
    /// A three-quarter view from the front that shows the whole box `min..max` on a canvas of
    /// the given aspect ratio (width / height).
    pub fn fit(min: Vec3, max: Vec3, aspect: f32) -> Orbit {
        let radius = (0.5 * (max - min).length()).max(1e-3);
        let half_fov = 0.5 * effective_fov(aspect);
        Orbit { target: 0.5 * (min + max), yaw: 0.6, pitch: 0.3, distance: 1.05 * radius / half_fov.sin(), radius }
    }

    /// Where the camera is.
    pub fn eye(&self, basis: &Basis) -> Vec3 {
        let horizontal = basis.back * self.yaw.cos() + basis.right * self.yaw.sin();
        let direction = horizontal * self.pitch.cos() + basis.up * self.pitch.sin();
        self.target + direction * self.distance
    }

    /// The camera turned by a pointer drag of (`dx`, `dy`) radians.
    pub fn rotated(self, dx: f32, dy: f32) -> Orbit {
        Orbit {
            yaw: (self.yaw - dx).rem_euclid(std::f32::consts::TAU),
            pitch: (self.pitch + dy).clamp(PITCH_RANGE.0, PITCH_RANGE.1),
            ..self
        }
    }

    /// The camera moved `factor` times closer (< 1) or farther (> 1), within limits.
    pub fn zoomed(self, factor: f32) -> Orbit {
        let (near, far) = (DISTANCE_RANGE.0 * self.radius, DISTANCE_RANGE.1 * self.radius);
        Orbit { distance: (self.distance * factor).clamp(near, far), ..self }
    }

    /// The follow camera: the same view slid along the floor until it looks down on `point` (the
    /// root), the target's height kept, so a walking subject stays in the middle of a zoomed view.
    pub fn following(self, point: Vec3, basis: &Basis) -> Orbit {
        Orbit { target: basis.on_floor(point, basis.height(self.target)), ..self }
    }

    /// Near clipping distance: small next to the scene, never zero.
    pub fn near(&self) -> f32 {
        (self.distance - 4.0 * self.radius).max(0.01 * self.radius).max(1e-4)
    }

    /// World → clip space for a canvas of the given aspect ratio.
    pub fn view_projection(&self, basis: &Basis, aspect: f32) -> Mat4 {
        let far = self.distance + 20.0 * self.radius;
        let projection = Mat4::perspective_rh(FOV_Y, aspect.max(1e-3), self.near(), far);
        let view = Mat4::look_at_rh(self.eye(basis), self.target, basis.up);
        projection * view
    }
}

/// The smaller of the vertical and horizontal field of view at this aspect ratio.
fn effective_fov(aspect: f32) -> f32 {
    let horizontal = 2.0 * ((0.5 * FOV_Y).tan() * aspect.max(1e-3)).atan();
    horizontal.min(FOV_Y)
}

/// A world → pixel projection for one canvas.
#[derive(Debug, Clone, Copy)]
pub struct Projector {
    matrix: Mat4,
    near: f32,
    size: Vec2,
}

impl Projector {
    pub fn new(orbit: &Orbit, basis: &Basis, size: Vec2) -> Projector {
        let aspect = size.x / size.y.max(1.0);
        Projector { matrix: orbit.view_projection(basis, aspect), near: orbit.near(), size }
    }

    /// Pixel position of a point in front of the camera; `None` behind it.
    pub fn point(&self, p: Vec3) -> Option<Vec2> {
        let clip = self.matrix * p.extend(1.0);
        (clip.w >= self.near).then(|| self.clip_to_pixels(clip))
    }

    /// Pixel end points of a segment, cut where it crosses the near plane; `None` if it lies
    /// entirely behind the camera.
    pub fn segment(&self, a: Vec3, b: Vec3) -> Option<(Vec2, Vec2)> {
        let (ca, cb) = (self.matrix * a.extend(1.0), self.matrix * b.extend(1.0));
        match (ca.w >= self.near, cb.w >= self.near) {
            (true, true) => Some((self.clip_to_pixels(ca), self.clip_to_pixels(cb))),
            (false, false) => None,
            (true, false) => Some((self.clip_to_pixels(ca), self.clip_to_pixels(self.cut(ca, cb)))),
            (false, true) => Some((self.clip_to_pixels(self.cut(cb, ca)), self.clip_to_pixels(cb))),
        }
    }

    /// The point between `inside` and `outside` (clip space) that lies on the near plane.
    fn cut(&self, inside: Vec4, outside: Vec4) -> Vec4 {
        let t = (inside.w - self.near) / (inside.w - outside.w);
        inside + (outside - inside) * t
    }

    fn clip_to_pixels(&self, clip: Vec4) -> Vec2 {
        let ndc = Vec2::new(clip.x, clip.y) / clip.w;
        Vec2::new((ndc.x + 1.0) * 0.5 * self.size.x, (1.0 - ndc.y) * 0.5 * self.size.y)
    }
}

/// The floor under a motion: a square grid at the lowest height the motion reaches, centred
/// under the box `min..max` and covering it with a margin.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorGrid {
    /// Height of the floor along the basis' up axis.
    pub height: f32,
    /// Grid spacing (a 1, 2 or 5 × 10ⁿ step, in file units).
    pub step: f32,
    /// The grid's lines, as end points in world coordinates.
    pub lines: Vec<(Vec3, Vec3)>,
}

impl FloorGrid {
    pub fn under(min: Vec3, max: Vec3, basis: &Basis) -> FloorGrid {
        let height = basis.height(min).min(basis.height(max));
        let centre = basis.on_floor(0.5 * (min + max), height);
        let half_extent = 0.5 * (max - min).length().max(1e-3);
        let step = nice_step(half_extent / 4.0);
        let half_lines = (1.25 * half_extent / step).ceil().max(1.0) as i32;
        let reach = half_lines as f32 * step;
        // Snap the centre to the grid so lines stay put relative to the world origin.
        let snap = |axis: Vec3| (centre.dot(axis) / step).round() * step;
        let origin = basis.up * height + basis.right * snap(basis.right) + basis.back * snap(basis.back);
        let mut lines = Vec::with_capacity(4 * half_lines as usize + 2);
        for i in -half_lines..=half_lines {
            let offset = i as f32 * step;
            let along_back = origin + basis.right * offset;
            lines.push((along_back - basis.back * reach, along_back + basis.back * reach));
            let along_right = origin + basis.back * offset;
            lines.push((along_right - basis.right * reach, along_right + basis.right * reach));
        }
        FloorGrid { height, step, lines }
    }
}

/// The smallest 1, 2 or 5 × 10ⁿ that is at least `x` (for grid spacings).
pub fn nice_step(x: f32) -> f32 {
    let x = x.max(1e-6);
    let decade = 10f32.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * decade).find(|s| *s >= x * 0.999).unwrap_or(10.0 * decade)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).length() < 1e-3
    }

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.8), 1.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(nice_step(1.5), 2.0);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert!((nice_step(0.03) - 0.05).abs() < 1e-7);
    }

    #[test]
    fn fitted_camera_sees_the_whole_box() {
        let (min, max) = (Vec3::new(-10.0, 0.0, -30.0), Vec3::new(10.0, 18.0, 30.0));
        for basis in [Basis::Y_UP, Basis::Z_UP] {
            let orbit = Orbit::fit(min, max, 16.0 / 9.0);
            let projector = Projector::new(&orbit, &basis, Vec2::new(1600.0, 900.0));
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                );
                let p = projector.point(corner).expect("corner in front of the camera");
                assert!((0.0..=1600.0).contains(&p.x) && (0.0..=900.0).contains(&p.y), "{p:?}");
            }
        }
    }

    #[test]
    fn the_follow_camera_keeps_the_root_on_the_middle_line_whatever_the_view() {
        for basis in [Basis::Y_UP, Basis::Z_UP] {
            let orbit = Orbit { target: Vec3::ZERO, yaw: 0.9, pitch: 0.4, distance: 3.0, radius: 1.0 };
            // a root 20 units away along the floor and 1 above the target's height
            let root = basis.right * 20.0 + basis.back * -7.0 + basis.up * 1.0;
            let size = Vec2::new(200.0, 100.0);
            // without following, it is off the canvas; following, it projects onto the vertical middle line
            let still = Projector::new(&orbit, &basis, size).point(root);
            assert!(still.is_none_or(|p| !(0.0..=200.0).contains(&p.x)), "{still:?}");
            let follow = orbit.following(root, &basis);
            assert!((basis.height(follow.target) - basis.height(orbit.target)).abs() < 1e-6);
            assert_eq!((follow.yaw, follow.pitch, follow.distance), (orbit.yaw, orbit.pitch, orbit.distance));
            let p = Projector::new(&follow, &basis, size).point(root).unwrap();
            assert!((p.x - 100.0).abs() < 1e-3 && p.y < 50.0, "{p:?}");
        }
    }

    #[test]
    fn target_projects_to_the_canvas_centre_and_up_is_up() {
        let orbit = Orbit::fit(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 1.0);
        let projector = Projector::new(&orbit, &Basis::Z_UP, Vec2::new(200.0, 100.0));
        assert!(close(projector.point(orbit.target).unwrap(), Vec2::new(100.0, 50.0)));
        let top = projector.point(Vec3::new(0.0, 0.0, 2.0)).unwrap();
        let bottom = projector.point(Vec3::ZERO).unwrap();
        assert!(top.y < bottom.y, "higher points are drawn higher on the canvas");
    }

    #[test]
    fn segments_are_cut_at_the_near_plane() {
        let orbit = Orbit { target: Vec3::ZERO, yaw: 0.0, pitch: 0.0, distance: 10.0, radius: 1.0 };
        let projector = Projector::new(&orbit, &Basis::Y_UP, Vec2::new(100.0, 100.0));
        let eye = orbit.eye(&Basis::Y_UP);
        assert_eq!(eye, Vec3::new(0.0, 0.0, 10.0));
        let behind = Vec3::new(0.0, 1.0, 20.0);
        assert!(projector.point(behind).is_none());
        assert!(projector.segment(behind, behind + Vec3::X).is_none());
        let (a, b) = projector.segment(Vec3::new(0.0, 1.0, 0.0), behind).expect("front part is kept");
        assert!(a.is_finite() && b.is_finite());
        assert!(close(a, projector.point(Vec3::new(0.0, 1.0, 0.0)).unwrap()));
    }

    #[test]
    fn orbit_limits() {
        let orbit = Orbit { target: Vec3::ZERO, yaw: 0.0, pitch: 0.0, distance: 10.0, radius: 1.0 };
        assert_eq!(orbit.rotated(0.0, 10.0).pitch, PITCH_RANGE.1);
        assert_eq!(orbit.zoomed(1e-6).distance, DISTANCE_RANGE.0);
        assert_eq!(orbit.zoomed(1e6).distance, DISTANCE_RANGE.1);
        let turned = orbit.rotated(std::f32::consts::PI, 0.0);
        assert!((turned.eye(&Basis::Y_UP) - Vec3::new(0.0, 0.0, -10.0)).length() < 1e-4);
    }

    #[test]
    fn grid_lies_on_the_lowest_point_of_a_z_up_motion() {
        let basis = Basis::Z_UP;
        let grid = FloorGrid::under(Vec3::new(-1.0, -1.0, 0.05), Vec3::new(1.0, 1.0, 1.8), &basis);
        assert!((grid.height - 0.05).abs() < 1e-6);
        assert!(!grid.lines.is_empty());
        for (a, b) in &grid.lines {
            assert!((a.z - 0.05).abs() < 1e-5 && (b.z - 0.05).abs() < 1e-5);
        }
        let reach = grid.lines.iter().map(|(a, _)| a.x.abs().max(a.y.abs())).fold(0.0, f32::max);
        assert!(reach >= 1.0, "grid covers the motion");
    }
}
