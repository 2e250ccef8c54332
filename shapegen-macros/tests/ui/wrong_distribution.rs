shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        params {
            n: int = normal(0, 1),
            x: f32 = uniform(0),
            v: vec3 = uniform([0.0, 0.0], [1.0, 1.0]),
        }
        |s| {}
    }
}
fn main() {}
