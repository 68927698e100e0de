//! Small ready-made models of the analytic surfaces and curves: planar
//! polygons, a cusp, an ellipse, a cylinder (whole and half), a cone and a
//! sphere, with their corners, curves, pcurves and loops.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::Arc;

use super::*;

fn line_use(curve: u32, forward: bool, origin: [f64; 2], dir: [f64; 2], seam: bool) -> CurveUse {
    CurveUse {
        curve: CurveId(curve),
        forward,
        pcurve: Arc::new(Line2d { origin, dir }),
        seam,
    }
}

/// A planar square `[0, side]²` in the z = 0 plane: 1 face, 4 line curves, 4 corners.
pub fn square(side: f64) -> Model {
    rectangle(side, side)
}

/// A planar rectangle `[0, width] × [0, height]` in the z = 0 plane: 1 face,
/// 4 line curves (bottom, right, top, left), 4 corners.
pub fn rectangle(width: f64, height: f64) -> Model {
    polygon(&[[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]])
}

/// A planar polygon through `points` (counter-clockwise, in the z = 0
/// plane): 1 face, one line curve from each point to the next, one corner
/// per point; (u, v) = (x, y) over the points' bounding box.
pub fn polygon(points: &[[f64; 2]]) -> Model {
    let n = points.len();
    let p: Vec<Vec3> = points.iter().map(|q| [q[0], q[1], 0.0]).collect();
    let corners = p.iter().map(|&point| Corner { point }).collect();
    let mut curves = Vec::new();
    let mut uses = Vec::new();
    for i in 0..n {
        let a = p[i];
        let b = p[(i + 1) % n];
        curves.push(CurveEntity {
            geom: Some(Arc::new(Line {
                origin: a,
                dir: sub(b, a),
                range: (0.0, 1.0),
            })),
            range: (0.0, 1.0),
            start: CornerId(i as u32),
            end: CornerId(((i + 1) % n) as u32),
            degenerate: false,
        });
        uses.push(line_use(
            i as u32,
            true,
            [a[0], a[1]],
            [b[0] - a[0], b[1] - a[1]],
            false,
        ));
    }
    let bounds = Bounds2 {
        umin: points.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min),
        umax: points
            .iter()
            .map(|q| q[0])
            .fold(f64::NEG_INFINITY, f64::max),
        vmin: points.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min),
        vmax: points
            .iter()
            .map(|q| q[1])
            .fold(f64::NEG_INFINITY, f64::max),
    };
    planar_model(corners, curves, uses, bounds)
}

/// A planar face with two cusps (0° corners): the x axis from (0, 0) to
/// (r, `tilt`), the line x = r up to (r, r), and the quarter circle of radius
/// r about (0, r) back to the origin, tangent to the axis at the origin and
/// to x = r at (r, r). `tilt` lifts the axis' far end (0 for the exact
/// shape), as rounding in a CAD file may leave the tangents of a cusp.
pub fn cusp(r: f64, tilt: f64) -> Model {
    let mut m = polygon(&[[0.0, 0.0], [r, tilt], [r, r]]);
    // the third side becomes the arc from the origin (t = −π/2) to (r, r)
    // (t = 0), used backwards
    m.curves[2] = CurveEntity {
        geom: Some(Arc::new(Circle {
            center: [0.0, r, 0.0],
            xdir: [1.0, 0.0, 0.0],
            ydir: [0.0, 1.0, 0.0],
            radius: r,
            range: (-FRAC_PI_2, 0.0),
        })),
        range: (-FRAC_PI_2, 0.0),
        start: CornerId(0),
        end: CornerId(2),
        degenerate: false,
    };
    m.faces[0].loops[0].uses[2] = CurveUse {
        curve: CurveId(2),
        forward: false,
        pcurve: Arc::new(Circle2d {
            center: [0.0, r],
            radius: r,
        }),
        seam: false,
    };
    m.faces[0].uv_bounds = Bounds2 {
        umin: 0.0,
        umax: r,
        vmin: tilt.min(0.0),
        vmax: r,
    };
    m
}

/// The planar ellipse `x²/a² + y²/b² ≤ 1` in the z = 0 plane: 1 face, two
/// half-ellipse curves (upper from (a, 0) to (−a, 0), lower back), 2 corners
/// at (±a, 0) — the coarse-method paper's Fig. 3 shape.
pub fn ellipse(a: f64, b: f64) -> Model {
    let corners = vec![Corner { point: [a, 0.0, 0.0] }, Corner { point: [-a, 0.0, 0.0] }];
    let half = |k: u32, range: (f64, f64)| CurveEntity {
        geom: Some(Arc::new(Ellipse {
            center: [0.0; 3],
            xdir: [1.0, 0.0, 0.0],
            ydir: [0.0, 1.0, 0.0],
            a,
            b,
            range,
        })),
        range,
        start: CornerId(k),
        end: CornerId(1 - k),
        degenerate: false,
    };
    let curves = vec![half(0, (0.0, PI)), half(1, (PI, TAU))];
    let uses = (0..2)
        .map(|k| CurveUse {
            curve: CurveId(k),
            forward: true,
            pcurve: Arc::new(Ellipse2d { center: [0.0, 0.0], a, b }),
            seam: false,
        })
        .collect();
    let bounds = Bounds2 { umin: -a, umax: a, vmin: -b, vmax: b };
    planar_model(corners, curves, uses, bounds)
}

/// One planar face in the z = 0 plane ((u, v) = (x, y)) with one loop.
fn planar_model(
    corners: Vec<Corner>,
    curves: Vec<CurveEntity>,
    uses: Vec<CurveUse>,
    bounds: Bounds2,
) -> Model {
    let plane = Plane {
        origin: [0.0; 3],
        xdir: [1.0, 0.0, 0.0],
        ydir: [0.0, 1.0, 0.0],
        bounds,
    };
    Model {
        corners,
        curves,
        faces: vec![Face {
            surface: Arc::new(plane),
            reversed: false,
            loops: vec![Loop { uses, outer: true }],
            uv_bounds: bounds,
        }],
    }
}

/// The cylinder of radius `r` about the z axis from z = 0 to `h`, (u, v) =
/// (angle from x, height): the side of [`cylinder`] and [`half_cylinder`].
fn z_cylinder(r: f64, h: f64) -> Arc<Cylinder> {
    Arc::new(Cylinder {
        center: [0.0; 3],
        xdir: [1.0, 0.0, 0.0],
        ydir: [0.0, 1.0, 0.0],
        radius: r,
        height: (0.0, h),
    })
}

/// The arc of radius `r` about the z axis at height `z`, from angle 0 (on
/// x) to `end`.
fn z_arc(r: f64, z: f64, end: f64) -> Circle {
    Circle {
        center: [0.0, 0.0, z],
        xdir: [1.0, 0.0, 0.0],
        ydir: [0.0, 1.0, 0.0],
        radius: r,
        range: (0.0, end),
    }
}

/// A closed cylinder solid of radius `r` and height `h` along z: a side face
/// (periodic, with a seam line) and two disc faces; 3 curves (2 circles, 1
/// seam), 2 corners. Normals point outward.
pub fn cylinder(r: f64, h: f64) -> Model {
    let x = [1.0, 0.0, 0.0];
    let y = [0.0, 1.0, 0.0];
    let corners = vec![
        Corner {
            point: [r, 0.0, 0.0],
        },
        Corner { point: [r, 0.0, h] },
    ];
    let circle = |z: f64| z_arc(r, z, TAU);
    let curves = vec![
        CurveEntity {
            geom: Some(Arc::new(circle(0.0))),
            range: (0.0, TAU),
            start: CornerId(0),
            end: CornerId(0),
            degenerate: false,
        },
        CurveEntity {
            geom: Some(Arc::new(circle(h))),
            range: (0.0, TAU),
            start: CornerId(1),
            end: CornerId(1),
            degenerate: false,
        },
        CurveEntity {
            geom: Some(Arc::new(Line {
                origin: [r, 0.0, 0.0],
                dir: [0.0, 0.0, 1.0],
                range: (0.0, h),
            })),
            range: (0.0, h),
            start: CornerId(0),
            end: CornerId(1),
            degenerate: false,
        },
    ];
    let side_bounds = Bounds2 {
        umin: 0.0,
        umax: TAU,
        vmin: 0.0,
        vmax: h,
    };
    let side = Face {
        surface: z_cylinder(r, h),
        reversed: false,
        loops: vec![Loop {
            uses: vec![
                line_use(0, true, [0.0, 0.0], [1.0, 0.0], false),
                line_use(2, true, [TAU, 0.0], [0.0, 1.0], true),
                line_use(1, false, [0.0, h], [1.0, 0.0], false),
                line_use(2, false, [0.0, 0.0], [0.0, 1.0], true),
            ],
            outer: true,
        }],
        uv_bounds: side_bounds,
    };
    let disc = |z: f64, curve: u32, reversed: bool| {
        let bounds = Bounds2 {
            umin: -r,
            umax: r,
            vmin: -r,
            vmax: r,
        };
        Face {
            surface: Arc::new(Plane {
                origin: [0.0, 0.0, z],
                xdir: x,
                ydir: y,
                bounds,
            }),
            reversed,
            loops: vec![Loop {
                uses: vec![CurveUse {
                    curve: CurveId(curve),
                    forward: true,
                    pcurve: Arc::new(Circle2d {
                        center: [0.0, 0.0],
                        radius: r,
                    }),
                    seam: false,
                }],
                outer: true,
            }],
            uv_bounds: bounds,
        }
    };
    Model {
        corners,
        curves,
        faces: vec![side, disc(0.0, 0, true), disc(h, 1, false)],
    }
}

/// Half of [`cylinder`]'s side: x² + y² = r², y ≥ 0, 0 ≤ z ≤ h, normal
/// outward, one face with no seam, (u, v) = (angle, height). Its loop is
/// the arc at z = 0 (curve 0), the line at x = −r (curve 1), the arc at
/// z = h (curve 2, used backwards) and the line at x = r (curve 3, used
/// backwards); 4 corners, (r, 0, 0), (−r, 0, 0), (−r, 0, h), (r, 0, h).
pub fn half_cylinder(r: f64, h: f64) -> Model {
    let corners = [[r, 0.0, 0.0], [-r, 0.0, 0.0], [-r, 0.0, h], [r, 0.0, h]]
        .map(|point| Corner { point })
        .to_vec();
    let arc = |z: f64| z_arc(r, z, PI);
    let line = |x0: f64| Line {
        origin: [x0, 0.0, 0.0],
        dir: [0.0, 0.0, 1.0],
        range: (0.0, h),
    };
    let curve = |geom: Arc<dyn Curve>, range: (f64, f64), a: u32, b: u32| CurveEntity {
        geom: Some(geom),
        range,
        start: CornerId(a),
        end: CornerId(b),
        degenerate: false,
    };
    let curves = vec![
        curve(Arc::new(arc(0.0)), (0.0, PI), 0, 1),
        curve(Arc::new(line(-r)), (0.0, h), 1, 2),
        curve(Arc::new(arc(h)), (0.0, PI), 3, 2),
        curve(Arc::new(line(r)), (0.0, h), 0, 3),
    ];
    // the pcurves share their curves' parameters
    let uses = vec![
        line_use(0, true, [0.0, 0.0], [1.0, 0.0], false),
        line_use(1, true, [PI, 0.0], [0.0, 1.0], false),
        line_use(2, false, [0.0, h], [1.0, 0.0], false),
        line_use(3, false, [0.0, 0.0], [0.0, 1.0], false),
    ];
    let face = Face {
        surface: z_cylinder(r, h),
        reversed: false,
        loops: vec![Loop { uses, outer: true }],
        uv_bounds: Bounds2 {
            umin: 0.0,
            umax: PI,
            vmin: 0.0,
            vmax: h,
        },
    };
    Model {
        corners,
        curves,
        faces: vec![face],
    }
}

/// The lateral face of a cone with its apex at the origin and its base circle
/// of radius `r` at height `h` (a [`Cone`] surface, normal pointing away from
/// the axis): one face bounded by a degenerate curve at the apex (curve 0,
/// v = apex), a seam line (curve 1) and the base circle (curve 2); 2 corners
/// (0 the apex, 1 on the base circle).
pub fn cone(r: f64, h: f64) -> Model {
    let s = Cone {
        radius: r,
        height: h,
        half_angle: r.atan2(h),
    };
    let va = s.apex_v();
    let corners = vec![Corner { point: [0.0; 3] }, Corner { point: [r, 0.0, h] }];
    let seam = Line {
        origin: [r, 0.0, h],
        dir: s.derivs([0.0, 0.0]).dv,
        range: (va, 0.0),
    };
    let base = Circle {
        center: [0.0, 0.0, h],
        xdir: [1.0, 0.0, 0.0],
        ydir: [0.0, 1.0, 0.0],
        radius: r,
        range: (0.0, TAU),
    };
    let curves = vec![
        CurveEntity {
            geom: None,
            range: (0.0, TAU),
            start: CornerId(0),
            end: CornerId(0),
            degenerate: true,
        },
        CurveEntity {
            geom: Some(Arc::new(seam)),
            range: (va, 0.0),
            start: CornerId(0),
            end: CornerId(1),
            degenerate: false,
        },
        CurveEntity {
            geom: Some(Arc::new(base)),
            range: (0.0, TAU),
            start: CornerId(1),
            end: CornerId(1),
            degenerate: false,
        },
    ];
    let face = Face {
        uv_bounds: s.uv_bounds(),
        surface: Arc::new(s),
        reversed: false,
        loops: vec![seam_band_loop(va, 0.0)],
    };
    Model {
        corners,
        curves,
        faces: vec![face],
    }
}

/// The loop of a face periodic in u over [0, 2π] between v = `v_low` and
/// `v_high`: curve 0 along v = `v_low` (u increasing), the seam (curve 1) at
/// u = 2π upwards, curve 2 along v = `v_high` backwards, the seam again at
/// u = 0 downwards (the cone's and the sphere's one face).
fn seam_band_loop(v_low: f64, v_high: f64) -> Loop {
    Loop {
        uses: vec![
            line_use(0, true, [0.0, v_low], [1.0, 0.0], false),
            line_use(1, true, [TAU, 0.0], [0.0, 1.0], true),
            line_use(2, false, [0.0, v_high], [1.0, 0.0], false),
            line_use(1, false, [0.0, 0.0], [0.0, 1.0], true),
        ],
        outer: true,
    }
}

/// A sphere of radius `r` at the origin: one face with a seam (a meridian) and
/// two degenerate curves at the poles; 2 corners (the poles).
pub fn sphere(r: f64) -> Model {
    let corners = vec![
        Corner {
            point: [0.0, 0.0, -r],
        },
        Corner {
            point: [0.0, 0.0, r],
        },
    ];
    let pole = |c: u32| CurveEntity {
        geom: None,
        range: (0.0, TAU),
        start: CornerId(c),
        end: CornerId(c),
        degenerate: true,
    };
    let meridian = Circle {
        center: [0.0; 3],
        xdir: [1.0, 0.0, 0.0],
        ydir: [0.0, 0.0, 1.0],
        radius: r,
        range: (-FRAC_PI_2, FRAC_PI_2),
    };
    let curves = vec![
        pole(0),
        CurveEntity {
            geom: Some(Arc::new(meridian)),
            range: (-FRAC_PI_2, FRAC_PI_2),
            start: CornerId(0),
            end: CornerId(1),
            degenerate: false,
        },
        pole(1),
    ];
    let s = Sphere {
        center: [0.0; 3],
        radius: r,
    };
    let face = Face {
        uv_bounds: s.uv_bounds(),
        surface: Arc::new(s),
        reversed: false,
        loops: vec![seam_band_loop(-FRAC_PI_2, FRAC_PI_2)],
    };
    Model {
        corners,
        curves,
        faces: vec![face],
    }
}

