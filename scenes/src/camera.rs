//! Camera math shared by the reference and every GPU method: one projection, one pixel-ray
//! convention, so that a rasterised pixel and a reference ray are the same line.
//!
//! Conventions: right-handed world, camera looks down -Z in view space, wgpu clip space
//! (x, y in [-1, 1], y up, depth in [0, 1]). Pixel (i, j) has j = 0 at the TOP row; its centre
//! is at NDC x = 2(i + ½)/W − 1, y = 1 − 2(j + ½)/H, which is where the rasteriser samples.

use glam::camera::rh::{proj::directx as proj, view};
use glam::dcamera::rh::{proj::directx as dproj, view as dview};
use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};

/// A camera at one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

impl CameraPose {
    pub fn view_from_world(&self) -> Mat4 {
        view::look_at_mat4(self.position, self.look_at, self.up)
    }

    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        proj::perspective(self.fov_y_deg.to_radians(), aspect, self.near, self.far)
    }

    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view_from_world()
    }

    /// world_from_view in f64: the camera's pose (view space: x right, y up, looking down −z).
    pub fn world_from_view(&self) -> DMat4 {
        dview::look_at_mat4(
            self.position.as_dvec3(),
            self.look_at.as_dvec3(),
            self.up.as_dvec3(),
        )
        .inverse()
    }

    /// A view-space point (m) in world space: where a camera-attached light sits.
    pub fn world_point(&self, view: Vec3) -> Vec3 {
        self.world_from_view()
            .transform_point3(view.as_dvec3())
            .as_vec3()
    }

    /// A view-space direction in world space, unit length (`view` need not be unit; not zero).
    pub fn world_direction(&self, view: Vec3) -> Vec3 {
        self.world_from_view()
            .transform_vector3(view.as_dvec3())
            .normalize()
            .as_vec3()
    }

    /// Unit forward vector (world).
    pub fn forward(&self) -> DVec3 {
        (self.look_at.as_dvec3() - self.position.as_dvec3()).normalize()
    }

    /// f64 rays through pixel centres, built from the same matrices the GPU uses.
    pub fn rays(&self, width: u32, height: u32) -> PixelRays {
        let aspect = width as f64 / height as f64;
        let view = dview::look_at_mat4(
            self.position.as_dvec3(),
            self.look_at.as_dvec3(),
            self.up.as_dvec3(),
        );
        let proj = dproj::perspective(
            (self.fov_y_deg as f64).to_radians(),
            aspect,
            self.near as f64,
            self.far as f64,
        );
        PixelRays {
            world_from_clip: (proj * view).inverse(),
            origin: self.position.as_dvec3(),
            forward: self.forward(),
            width,
            height,
            near: self.near as f64,
            far: self.far as f64,
        }
    }
}

/// Generates the ray through any pixel of a `width`×`height` image.
#[derive(Clone, Copy, Debug)]
pub struct PixelRays {
    world_from_clip: DMat4,
    pub origin: DVec3,
    pub forward: DVec3,
    pub width: u32,
    pub height: u32,
    pub near: f64,
    pub far: f64,
}

impl PixelRays {
    /// NDC (x, y) of the centre of pixel (i, j).
    pub fn ndc(&self, i: u32, j: u32) -> (f64, f64) {
        (
            2.0 * (i as f64 + 0.5) / self.width as f64 - 1.0,
            1.0 - 2.0 * (j as f64 + 0.5) / self.height as f64,
        )
    }

    /// Unit direction of the ray through the centre of pixel (i, j).
    pub fn direction(&self, i: u32, j: u32) -> DVec3 {
        let (x, y) = self.ndc(i, j);
        let p = self.world_from_clip * DVec4::new(x, y, 1.0, 1.0); // a point on the far plane
        (p.truncate() / p.w - self.origin).normalize()
    }

    /// Distance along a ray of direction `dir` to the far plane (view depth = far): where a
    /// ray that hits nothing ends.
    pub fn far_distance(&self, dir: DVec3) -> f64 {
        self.far / dir.dot(self.forward)
    }

    /// Distance along `dir` to the near plane; surfaces closer than this are clipped.
    pub fn near_distance(&self, dir: DVec3) -> f64 {
        self.near / dir.dot(self.forward)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose() -> CameraPose {
        CameraPose {
            position: Vec3::new(1.0, 2.0, 6.0),
            look_at: Vec3::new(0.0, 0.5, 0.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
            near: 0.1,
            far: 40.0,
        }
    }

    /// The pixel-centre ray convention matches the view-projection matrix the GPU rasterises with:
    /// projecting a point on pixel (i, j)'s ray lands on that pixel's centre.
    #[test]
    fn pixel_rays_project_back_to_their_pixel_centres() {
        let cam = pose();
        let (w, h) = (37u32, 23u32);
        let rays = cam.rays(w, h);
        let clip_from_world = cam.clip_from_world(w as f32 / h as f32);
        for (i, j) in [(0, 0), (36, 22), (18, 11), (5, 19), (30, 2)] {
            let d = rays.direction(i, j);
            for t in [0.5, 3.0, 20.0] {
                let p = rays.origin + d * t;
                let c = clip_from_world * p.as_vec3().extend(1.0);
                let (nx, ny) = (c.x / c.w, c.y / c.w);
                // Framebuffer coordinates: x right, y down, pixel centres at +0.5.
                let fx = (nx + 1.0) * 0.5 * w as f32;
                let fy = (1.0 - ny) * 0.5 * h as f32;
                assert!(
                    (fx - (i as f32 + 0.5)).abs() < 1e-3 && (fy - (j as f32 + 0.5)).abs() < 1e-3,
                    "pixel ({i},{j}) projects to ({fx},{fy})"
                );
            }
        }
    }

    #[test]
    fn far_distance_lands_on_the_far_plane() {
        let cam = pose();
        let rays = cam.rays(16, 16);
        let d = rays.direction(0, 15);
        let p = rays.origin + d * rays.far_distance(d);
        // View depth in f64 (the f32 view matrix alone is good to ~1e-7 relative).
        let depth = (p - rays.origin).dot(cam.forward());
        assert!((depth - 40.0).abs() < 1e-9);
    }
}
