shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    limits: { min_len: 0, max_len: 0 };
    node A { |s| {} }
}
fn main() {}
