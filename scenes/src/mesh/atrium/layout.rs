//! The atrium's plan: where the columns, bays, banners and torches are, in world metres.
//! One place for every dimension, so the geometry, the library file's lights and the
//! light-count variants agree.

use glam::{Mat4, Vec3, Vec4};

/// Half extents of the column ring (column centres), m: x = ±10, z = ±22.
pub const RING_HALF: [f32; 2] = [10.0, 22.0];
/// Distance between column centres, m.
pub const BAY: f32 = 4.0;
/// Half extents of the outer walls' inner faces, m (a 4 m ambulatory behind the columns).
pub const WALL_HALF: [f32; 2] = [14.0, 26.0];
/// Wall thickness, m.
pub const WALL: f32 = 0.4;

/// One storey of the arcade, heights in m.
#[derive(Clone, Copy, Debug)]
pub struct Storey {
    /// Floor level of the storey (column base).
    pub floor: f32,
    /// Column height (base to abacus top), where the arches spring.
    pub column: f32,
    /// Height of the spandrel wall above the springing line.
    pub spandrel: f32,
}

impl Storey {
    pub fn spring(&self) -> f32 {
        self.floor + self.column
    }
    pub fn top(&self) -> f32 {
        self.spring() + self.spandrel
    }
}

pub const GROUND: Storey = Storey {
    floor: 0.0,
    column: 5.0,
    spandrel: 2.2,
};
pub const UPPER: Storey = Storey {
    floor: 7.5,
    column: 4.0,
    spandrel: 1.7,
};
/// Gallery slab (the upper storey's floor) thickness: from GROUND.top() to UPPER.floor.
pub const SLAB: f32 = UPPER.floor - (GROUND.column + GROUND.spandrel);
/// Roof thickness, m; the roof sits on UPPER.top().
pub const ROOF: f32 = 0.4;
/// Half extents of the roof opening over the courtyard, m.
pub const OPENING_HALF: [f32; 2] = [6.0, 16.0];
/// Spandrel and arch depth (across the wall), m.
pub const ARCADE_DEPTH: f32 = 0.7;
/// Half width of the abacus the arches spring from, m.
pub const ABACUS_HALF: f32 = 0.55;

/// A column of the ring: its centre on the floor plane and the unit direction toward the
/// courtyard's centre line (where the torch bracket points).
#[derive(Clone, Copy, Debug)]
pub struct RingColumn {
    pub x: f32,
    pub z: f32,
    pub inward: Vec3,
}

/// The 32 columns of one storey in ring order: up the +x side (z increasing), along +z (x
/// decreasing), down the −x side, along −z; corners once.
pub fn ring() -> Vec<RingColumn> {
    let [hx, hz] = RING_HALF;
    let along = |n: f32| (0..=(n as i32)).map(move |i| i as f32 * BAY);
    let mut out = Vec::with_capacity(32);
    for dz in along(2.0 * hz / BAY) {
        out.push((hx, -hz + dz));
    }
    for dx in along(2.0 * hx / BAY).skip(1).take(4) {
        out.push((hx - dx, hz));
    }
    for dz in along(2.0 * hz / BAY) {
        out.push((-hx, hz - dz));
    }
    for dx in along(2.0 * hx / BAY).skip(1).take(4) {
        out.push((-hx + dx, -hz));
    }
    out.into_iter()
        .map(|(x, z)| {
            // Corners point diagonally inward; side columns straight across.
            let ix = if x.abs() == hx { -x.signum() } else { 0.0 };
            let iz = if z.abs() == hz { -z.signum() } else { 0.0 };
            RingColumn {
                x,
                z,
                inward: Vec3::new(ix, 0.0, iz).normalize(),
            }
        })
        .collect()
}

/// One bay of the ring: the frame that maps bay-local coordinates (u along the arcade from
/// −BAY/2 to BAY/2, y up from the springing line, w across the wall toward the courtyard) to
/// world space. The matrix is an exact axis permutation plus a translation, so instances of
/// one mesh stay bitwise consistent.
pub fn bays(storey: &Storey) -> Vec<Mat4> {
    let [hx, hz] = RING_HALF;
    let y = storey.spring();
    let mut out = Vec::new();
    let steps =
        |half: f32| (0..(2.0 * half / BAY) as i32).map(move |i| -half + (i as f32 + 0.5) * BAY);
    for z in steps(hz) {
        // u → +z, w → −x (toward the courtyard) on the +x side; mirrored on the −x side.
        out.push(frame(Vec3::Z, Vec3::NEG_X, Vec3::new(hx, y, z)));
        out.push(frame(Vec3::NEG_Z, Vec3::X, Vec3::new(-hx, y, z)));
    }
    for x in steps(hx) {
        out.push(frame(Vec3::NEG_X, Vec3::NEG_Z, Vec3::new(x, y, hz)));
        out.push(frame(Vec3::X, Vec3::Z, Vec3::new(x, y, -hz)));
    }
    out
}

/// The four arcade walls of a storey: (world_from_wall, bays), the wall's local frame as in
/// [`bays`] with its origin at the middle of the side, on the springing line.
pub fn walls(storey: &Storey) -> Vec<(Mat4, u32)> {
    let [hx, hz] = RING_HALF;
    let y = storey.spring();
    let (long, short) = ((2.0 * hz / BAY) as u32, (2.0 * hx / BAY) as u32);
    vec![
        (frame(Vec3::Z, Vec3::NEG_X, Vec3::new(hx, y, 0.0)), long),
        (frame(Vec3::NEG_Z, Vec3::X, Vec3::new(-hx, y, 0.0)), long),
        (
            frame(Vec3::NEG_X, Vec3::NEG_Z, Vec3::new(0.0, y, hz)),
            short,
        ),
        (frame(Vec3::X, Vec3::Z, Vec3::new(0.0, y, -hz)), short),
    ]
}

/// world_from_bay with bay axes u (along), Y (up) and w = u × Y (so the frame is a rotation).
pub fn frame(u: Vec3, w: Vec3, origin: Vec3) -> Mat4 {
    debug_assert_eq!(u.cross(Vec3::Y), w, "bay frame must be right-handed");
    Mat4::from_cols(u.extend(0.0), Vec4::Y, w.extend(0.0), origin.extend(1.0))
}

/// Height of a ground-storey torch above the floor, m.
const GROUND_TORCH_Y: f32 = 3.4;
/// Height of an upper-storey torch above the gallery floor, m.
const UPPER_TORCH_RISE: f32 = 2.6;
/// Distance of a torch from its column's axis toward the courtyard, m.
const TORCH_REACH: f32 = 0.6;
/// Most torches the atrium has sconces for (one per column and storey).
pub const MAX_TORCHES: usize = 64;

/// The first `n` (≤ [`MAX_TORCHES`]) torch positions. The order spreads any prefix evenly:
/// ground-storey columns in bit-reversed ring order (so 4 torches sit at the ring's quarter
/// points and 16 on every other column), then the upper storey in the same order.
pub fn torches(n: usize) -> Vec<Vec3> {
    let ring = ring();
    let bits = ring.len().trailing_zeros();
    let reversed = |i: usize| i.reverse_bits() >> (usize::BITS - bits);
    let storeys = [GROUND_TORCH_Y, UPPER.floor + UPPER_TORCH_RISE];
    storeys
        .iter()
        .flat_map(|&y| {
            (0..ring.len()).map({
                let ring = &ring;
                move |i| {
                    let c = ring[reversed(i)];
                    Vec3::new(c.x, y, c.z) + c.inward * TORCH_REACH
                }
            })
        })
        .take(n.min(MAX_TORCHES))
        .collect::<Vec<_>>()
}

/// Centres (top edge midpoints) of the banners and the unit direction they face (toward the
/// courtyard). Alternate bays of the long sides, and the two middle bays of the far (−z) side.
pub fn banners() -> Vec<(Vec3, Vec3)> {
    let [hx, hz] = RING_HALF;
    let top = UPPER.spring() + 1.3;
    let inset = 0.55;
    let mut out = Vec::new();
    for i in (1..(2.0 * hz / BAY) as i32).step_by(2) {
        let z = -hz + (i as f32 + 0.5) * BAY;
        out.push((Vec3::new(hx - inset, top, z), Vec3::NEG_X));
        out.push((Vec3::new(-hx + inset, top, z), Vec3::X));
    }
    // Bay centres of the short side lie at 0, ±BAY, ±2·BAY (columns at ±BAY/2, ±3·BAY/2).
    for x in [-BAY, BAY] {
        out.push((Vec3::new(x, top, -hz + inset), Vec3::Z));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ring_has_32_distinct_columns_on_the_rectangle() {
        let r = ring();
        assert_eq!(r.len(), 32);
        for (i, a) in r.iter().enumerate() {
            assert!(a.x.abs() == RING_HALF[0] || a.z.abs() == RING_HALF[1]);
            for b in &r[i + 1..] {
                assert!((a.x, a.z) != (b.x, b.z), "column twice at {}, {}", a.x, a.z);
            }
            // Inward points toward the centre.
            assert!(a.inward.dot(Vec3::new(-a.x, 0.0, -a.z)) > 0.0);
        }
    }

    #[test]
    fn torch_prefixes_spread_over_the_ring() {
        let all = torches(MAX_TORCHES);
        assert_eq!(all.len(), 64);
        // 64 distinct positions.
        for (i, a) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|b| (*a - *b).length() > 1.0));
        }
        // The first four sit in four different quadrants (about the courtyard centre).
        let quadrant = |p: &Vec3| (p.x > 0.0, p.z > 0.0);
        let four: Vec<_> = torches(4).iter().map(quadrant).collect();
        for (i, q) in four.iter().enumerate() {
            assert!(!four[i + 1..].contains(q), "two of the first four in {q:?}");
        }
        // 16 torches: the ground storey only, every other column.
        assert!(torches(16).iter().all(|p| p.y == GROUND_TORCH_Y));
    }

    #[test]
    fn bay_frames_are_rigid_and_sit_on_the_ring() {
        for storey in [GROUND, UPPER] {
            let frames = bays(&storey);
            assert_eq!(frames.len(), 32);
            for m in frames {
                assert!((m.determinant() - 1.0).abs() < 1e-6);
                let o = m.w_axis.truncate();
                assert!(o.x.abs() == RING_HALF[0] || o.z.abs() == RING_HALF[1]);
                assert_eq!(o.y, storey.spring());
            }
        }
    }
}
