// The one source of the precompiled-header owners (cmake/SwarmformPch.cmake): a target needs a source to
// compile its header, and this one adds nothing else.
