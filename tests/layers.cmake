# The layering of the source tree (docs/architecture.md): no file includes a
# header of a higher layer. The second test checks that the check can fail:
# it copies the tree with one upward include added and expects a failure.
add_test(NAME layers.no_upward_include COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/check-layers.sh ${PROJECT_SOURCE_DIR})
add_test(NAME layers.check_fails_on_upward_include
         COMMAND bash ${PROJECT_SOURCE_DIR}/tests/layers_check_fails.sh ${PROJECT_SOURCE_DIR})
