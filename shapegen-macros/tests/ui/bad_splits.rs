shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        slots { left: B = 1.0, right: B = 1.0, c: C = 1.0 }
        |s| {
            split!(s, w, [left: 1.0]);
            split!(s, x, [left: 1.0, rigth: rel(1.0)]);
            child!(right, s);
            child!(c, s);
        }
    }
    node C {
        slots { b: B = 1.0 }
        |s| {
            split!(s, x, [b: 1.0]);
            split!(s, y, [b: 1.0]);
        }
    }
    node B emits {
        |s| { emit!(cube, s.instance()); }
    }
}
fn main() {}
