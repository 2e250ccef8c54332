shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        parameters { x: f32 = uniform(0, 1) }
        |s| {}
    }
}
fn main() {}
