shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        params { x: f32 = uniform(0, 1), x: f32 = uniform(0, 2) }
        slots { next: A = 0.5, next: A = 0.5 }
        |s| {}
    }
}
fn main() {}
