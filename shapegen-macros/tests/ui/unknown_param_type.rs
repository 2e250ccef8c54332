shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        params { q: vec4 = uniform(0, 1) }
        |s| {}
    }
}
fn main() {}
